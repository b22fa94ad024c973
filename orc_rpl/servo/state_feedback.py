"""The servo room's state feedback for elastic gears: per-joint LQR on the two-mass model with a Kalman observer, every 1 ms step."""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.linalg

from orc_rpl.robot.friction import friction_torque_nm
from orc_rpl.robot.model import ArmModel
from orc_rpl.servo.control import FRICTION_SMOOTH_RAD_S

#: The closed-loop bandwidth (rad/s) of each joint's link position: the LQR's link poles sit there (damping
#: about 0.8), above the anti-resonance where the cascade had to stay below it (j1 38, j2 48 rad/s).
LINK_BANDWIDTH_RAD_S = 80.0
#: The LQR's weight on the motor's angle and speed errors, as a share of the link's (the rotor's own mode is
#: damped through them; the link's error is what the tool shows).
MOTOR_WEIGHT = 0.1
#: Link inertias the gains are designed for: this many values per joint, log-spaced from LINK_SPAN[0] times the
#: model's smallest M_ii - J_rotor to LINK_SPAN[1] times its largest (payloads included), interpolated between.
GRID_POINTS = 24
LINK_SPAN = (0.5, 2.0)
#: The Kalman observer's assumptions (1 sigma): torques on the rotor and on the link the model does not know,
#: as white noise (N m sqrt(s)), the link's unknown torque as a random walk (N m / sqrt(s)), the encoder's angle
#: (rad) and the drive's speed measurement (rad/s).
ROTOR_NOISE_NM = 2.0
LINK_NOISE_NM = 2.0
DISTURBANCE_WALK_NM = 150.0
ANGLE_NOISE_RAD = 1e-4
SPEED_NOISE_RAD_S = 2e-2
#: A joint's reference moving faster than this (rad/s): the observer's unknown torque is the link's (an undeclared
#: payload's, passing through the gear and twisting it); slower, the rotor's (at rest the motor side cannot tell the
#: rotor's static friction from the link's torque, and the friction acts on the rotor). As GearTwist's hold.
MOVING_RAD_S = 0.2

#: Joints whose anti-resonance at the links' largest inertia is above this (rad/s) keep the cascade (servo/control.py)
#: on the twisted references: the rigid tuning's velocity loop is below their anti-resonance anyway (two_mass.py).
STATE_FEEDBACK_BELOW_RAD_S = 160.0

#: The speed (per rad of the rotor's error) added to the reference's for the sign of the Coulomb feed-forward,
#: as the cascade's position gain does it: a rotor stuck short of its target gets its friction fed forward.
FRICTION_POSITION_GAIN_1_S = 40.0


def two_mass_model(rotor_kg_m2: float, link_kg_m2: float, stiffness_nm_rad: float, damping_nm_s: float,
                   period_s: float, on_link: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """One joint's two-mass model sampled with the torque held over each period (zero-order hold).

    State (theta, theta', q, q', w): the rotor's angle and speed, the link's, and the link's unknown torque
    w (constant in the model; on the rotor instead, `on_link=False`: J_r theta'' = ... + w). Inputs (u, b): the motor's torque less the rotor's friction, and the link's
    torque other than its own inertia's (gravity, Coriolis, the other joints' accelerations):
    J_r theta'' = u - k (theta - q) - d (theta' - q'),  J_l q'' = k (theta - q) + d (theta' - q') - b + w.
    """
    k, d, jr, jl = stiffness_nm_rad, damping_nm_s, rotor_kg_m2, link_kg_m2
    a = np.zeros((7, 7))   # [A B; 0 0]: expm gives (Ad, Bd) at once
    a[0, 1] = a[2, 3] = 1.0
    a[1, :4] = (-k / jr, -d / jr, k / jr, d / jr)
    a[3, :4] = (k / jl, d / jl, -k / jl, -d / jl)
    a[3 if on_link else 1, 4] = 1.0 / (jl if on_link else jr)
    a[1, 5], a[3, 6] = 1.0 / jr, -1.0 / jl
    e = scipy.linalg.expm(a * period_s)
    return e[:5, :5], e[:5, 5:]


def lqr_gain(ad: np.ndarray, bd: np.ndarray, rotor_kg_m2: float, link_kg_m2: float,
             bandwidth_rad_s: float, motor_weight: float | None = None) -> np.ndarray:
    """The discrete LQR's gain on (theta, theta', q, q') errors: link poles at about `bandwidth_rad_s`.

    The weights are a double integrator's of the whole joint's inertia J (its LQR with weights (J w^2)^2 on
    the angle and 1 on the torque puts its poles at w with damping 0.7), on the link, and `motor_weight` of
    it on the rotor.
    """
    motor_weight = MOTOR_WEIGHT if motor_weight is None else motor_weight
    j, w = rotor_kg_m2 + link_kg_m2, bandwidth_rad_s
    angle, speed = (j * w * w) ** 2, 0.5 * (j * w) ** 2
    q = np.diag([motor_weight * angle, motor_weight * speed, angle, speed])
    a4, b4, r = ad[:4, :4], bd[:4, :1], np.eye(1)
    p = scipy.linalg.solve_discrete_are(a4, b4, q, r)
    return np.linalg.solve(r + b4.T @ p @ b4, b4.T @ p @ a4)[0]


def kalman_gain(ad: np.ndarray, rotor_kg_m2: float, link_kg_m2: float, period_s: float) -> np.ndarray:
    """The steady Kalman filter's correction gain (5 x 2) from the encoder's angle and the drive's speed."""
    c = np.zeros((2, 5))
    c[0, 0] = c[1, 1] = 1.0
    qd = np.diag([0.0, (ROTOR_NOISE_NM / rotor_kg_m2) ** 2, 0.0, (LINK_NOISE_NM / link_kg_m2) ** 2,
                  DISTURBANCE_WALK_NM ** 2]) * period_s
    rd = np.diag([ANGLE_NOISE_RAD ** 2, SPEED_NOISE_RAD_S ** 2])
    p = scipy.linalg.solve_discrete_are(ad.T, c.T, qd, rd)   # the prior's covariance
    return p @ c.T @ np.linalg.inv(c @ p @ c.T + rd)


def link_inertia_range(arm: ArmModel, rotor_kg_m2: np.ndarray, points: int = 7) -> tuple[np.ndarray, np.ndarray]:
    """Each joint's smallest and largest link-side inertia (M_ii less the rotor) over j2 and j3's ranges."""
    base, low, high = np.array(arm.home_q, dtype=float), np.full(arm.n_joints, np.inf), np.zeros(arm.n_joints)
    for a in np.linspace(arm.q_min[1], arm.q_max[1], points):
        for b in np.linspace(arm.q_min[2], arm.q_max[2], points):
            q = base.copy()
            q[1], q[2] = a, b
            m = arm.mass_matrix_diagonal_unchecked(q) - rotor_kg_m2
            np.minimum(low, m, out=low)
            np.maximum(high, m, out=high)
    return np.maximum(low, 1e-6), np.maximum(high, 1e-6)


class TwoMassStateFeedback:
    """State feedback for joints whose gear is a spring: the torque from the rotor's and the link's states.

    Each slow joint (anti-resonance below STATE_FEEDBACK_BELOW_RAD_S: `joints`) is a two-mass system
    (`two_mass_model`) whose link inertia the model computes for the pose (M_ii less the rotor, every
    `schedule`). The rotor's reference leads the link's by the twist the link torque needs (the model's,
    less the observer's unknown torque w); the feed-forward is the model's torque, its friction estimate,
    and -w; the feedback is the LQR's gain (`lqr_gain`) on the errors of the rotor's angle and speed and
    of the link's, the link's as a Kalman observer (`kalman_gain`) estimates them from the encoder and
    the drive's speed every 1 ms step. The observer's w is the integral action: a torque the model lacks
    (an undeclared payload's weight) is estimated and fed forward, in the torque and in the twist. Gains
    and observer are designed per joint from the controller's model (nominal stiffness, damping and
    inertias) on a grid of link inertias and interpolated (`GRID_POINTS`); nothing of the plant's own
    parameters. The other joints' rotors get the twist of the model's link torque (`twist_rad`) and keep
    the cascade (ServoLoop runs it).
    """

    def __init__(self, arm: ArmModel, rotor_kg_m2: Any, stiffness_nm_rad: Any, damping_nm_s: Any, period_s: float,
                 bandwidth_rad_s: float | None = None) -> None:
        """bandwidth_rad_s: the links' closed-loop bandwidth (None: LINK_BANDWIDTH_RAD_S)."""
        self.arm, self.period_s = arm, float(period_s)
        bandwidth_rad_s = LINK_BANDWIDTH_RAD_S if bandwidth_rad_s is None else float(bandwidth_rad_s)
        n = arm.n_joints
        rotor = np.asarray(rotor_kg_m2, dtype=float)
        stiffness = np.asarray(stiffness_nm_rad, dtype=float)
        self.rotor_all, self.stiffness_all = rotor, stiffness
        low, high = link_inertia_range(arm, rotor)
        #: the joints under state feedback (the slow gears), the others' indices in `cascade`
        self.joints = np.flatnonzero(np.sqrt(stiffness / high) < STATE_FEEDBACK_BELOW_RAD_S)
        self.cascade = np.setdiff1d(np.arange(n), self.joints)
        sel = self.joints
        self.rotor, self.stiffness = rotor[sel], stiffness[sel]
        self.damping = np.asarray(damping_nm_s, dtype=float)[sel]
        self.tau_max = np.array(arm.tau_max, dtype=float)[sel]
        m = len(sel)
        self.grid = np.exp(np.linspace(np.log(low[sel] * LINK_SPAN[0]), np.log(high[sel] * LINK_SPAN[1]), GRID_POINTS)).T
        shape = (m, GRID_POINTS)
        self._ad, self._bd = np.zeros(shape + (5, 5)), np.zeros(shape + (5, 2))
        self._k, self._l = np.zeros(shape + (4,)), np.zeros(shape + (5, 2))
        self._ad_m, self._l_m = np.zeros(shape + (5, 5)), np.zeros(shape + (5, 2))   #: w on the rotor (at rest)
        for j in range(m):
            for g, link in enumerate(self.grid[j]):
                ad, bd = two_mass_model(self.rotor[j], link, self.stiffness[j], self.damping[j], self.period_s)
                self._ad[j, g], self._bd[j, g] = ad, bd
                self._k[j, g] = lqr_gain(ad, bd, self.rotor[j], link, bandwidth_rad_s)
                self._l[j, g] = kalman_gain(ad, self.rotor[j], link, self.period_s)
                ad, _ = two_mass_model(self.rotor[j], link, self.stiffness[j], self.damping[j], self.period_s, False)
                self._ad_m[j, g], self._l_m[j, g] = ad, kalman_gain(ad, self.rotor[j], link, self.period_s)
        self.link_kg_m2 = self.grid[:, GRID_POINTS // 2].copy()   #: the slow joints' link inertias the gains are for now
        self.ad, self.bd, self.k, self.l = (self._ad[:, 0], self._bd[:, 0], self._k[:, 0], self._l[:, 0])
        self.ad_m, self.l_m = self._ad_m[:, 0], self._l_m[:, 0]
        #: per slow joint: True while its reference moves faster than MOVING_RAD_S (the observer's w is then the
        #: link's unknown torque, the rotor's held), False at rest (w the rotor's, the link's held)
        self.moving = np.zeros(m, dtype=bool)
        self.held_link_nm, self.held_rotor_nm = np.zeros(m), np.zeros(m)
        self.state = np.zeros((m, 5))            #: the observer's (theta, theta', q, q', w) per slow joint
        self.twist_rad = np.zeros(n)             #: the twist of the last row commanded, every joint (rad)
        self.friction: tuple[np.ndarray, np.ndarray] | None = None   #: the rotors' friction estimate (all joints)
        self._rows = np.arange(m)
        self._link_other = np.zeros(m)

    def schedule(self, q: np.ndarray) -> None:
        """Gains and observer for the link inertias at pose q (the model's M_ii less the rotor), interpolated."""
        link = np.asarray(self.arm.mass_matrix_diagonal_unchecked(q))[self.joints] - self.rotor
        self.link_kg_m2 = link
        at = np.empty(len(link))
        for j in range(len(link)):
            at[j] = np.interp(np.log(max(link[j], 1e-9)), np.log(self.grid[j]), np.arange(GRID_POINTS))
        lo = np.minimum(np.floor(at).astype(int), GRID_POINTS - 2)
        f = at - lo
        rows = self._rows

        def blend(table: np.ndarray) -> np.ndarray:
            shape = (-1,) + (1,) * (table.ndim - 2)
            return table[rows, lo] * (1.0 - f).reshape(shape) + table[rows, lo + 1] * f.reshape(shape)

        self.ad, self.bd, self.k, self.l = blend(self._ad), blend(self._bd), blend(self._k), blend(self._l)
        self.ad_m, self.l_m = blend(self._ad_m), blend(self._l_m)

    def reset(self, q_link: np.ndarray, link_torque_nm: np.ndarray) -> None:
        """At rest, the links at q_link carrying link_torque_nm (the model's weight): the rotors ahead by the twist."""
        q_link = np.asarray(q_link, dtype=float)
        self.schedule(q_link)
        self.twist_rad = np.asarray(link_torque_nm, dtype=float) / self.stiffness_all
        sel = self.joints
        self.state[:] = 0.0
        self.state[:, 0], self.state[:, 2] = q_link[sel] + self.twist_rad[sel], q_link[sel]
        self.moving[:] = False
        self.held_link_nm[:] = self.held_rotor_nm[:] = 0.0

    hold = reset   #: the name ServoLoop.reset calls a twist's (at rest, the rotors ahead of the links by it)

    @property
    def link_w_nm(self) -> np.ndarray:
        """The slow joints' unknown link torque w (N m; the model's link torque less it is the gear's)."""
        return np.where(self.moving, self.state[:, 4], self.held_link_nm)

    @property
    def rotor_w_nm(self) -> np.ndarray:
        """The slow joints' unknown torque on the rotor (N m; the motor's torque less it drives the rotor)."""
        return np.where(self.moving, self.held_rotor_nm, self.state[:, 4])

    @property
    def unknown_torque_nm(self) -> np.ndarray:
        """The slow joints' torque the model lacks, as the observer estimates it (N m, added to the model's)."""
        return -(self.link_w_nm + self.rotor_w_nm)

    def _switch(self, moving: np.ndarray) -> None:
        """Joints whose reference starts or stops moving: w changes sides, the other side's held."""
        change = moving != self.moving
        if not change.any():
            return
        w = self.state[:, 4]
        start, stop = change & moving, change & ~moving
        self.held_rotor_nm[start], w[start] = w[start], self.held_link_nm[start]
        self.held_link_nm[stop], w[stop] = w[stop], self.held_rotor_nm[stop]
        self.moving = moving.copy()

    def references(self, q_ref: np.ndarray, qd_ref: np.ndarray, qdd_ref: np.ndarray,
                   tau_ff: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The rotors' reference angles and speeds for one row of link references (every joint): the link's plus
        the twist of the link torque (the slow joints' less the observer's w), its rate from the last row's."""
        sel = self.joints
        self._switch(np.abs(qd_ref[sel]) > MOVING_RAD_S)
        link_torque = tau_ff - self.rotor_all * qdd_ref
        w_link = self.link_w_nm
        link_torque[sel] -= w_link
        twist = link_torque / self.stiffness_all
        rate = (twist - self.twist_rad) / self.period_s
        self.twist_rad = twist
        # the link's torque other than its inertia's, less the held unknown torque at rest (an input then)
        self._link_other = link_torque[sel] + np.where(self.moving, w_link, 0.0) - self.link_kg_m2 * qdd_ref[sel]
        return q_ref + twist, qd_ref + rate

    def update(self, q_ref: np.ndarray, qd_ref: np.ndarray, theta_ref: np.ndarray, theta_d_ref: np.ndarray,
               tau_ff: np.ndarray, theta: np.ndarray, theta_d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """One 1 ms step of the slow joints (call `references` first, `applied` after): the demanded motor torque
        (before the drive's limit) and its feed-forward. Arguments are every joint's: the link's and the
        rotor's reference rows, the model's torque of the link reference (the rotor's inertia included), and
        the encoder's angle and the drive's speed now."""
        sel, x = self.joints, self.state
        innovation = np.stack([theta[sel] - x[:, 0], theta_d[sel] - x[:, 1]], axis=1)
        gain = np.where(self.moving[:, None, None], self.l, self.l_m)
        x += np.einsum("jab,jb->ja", gain, innovation)
        rotor, rotor_d = theta_ref[sel], theta_d_ref[sel]
        error = np.stack([x[:, 0] - rotor, x[:, 1] - rotor_d, x[:, 2] - q_ref[sel], x[:, 3] - qd_ref[sel]], axis=1)
        ff = tau_ff[sel] - self.link_w_nm - self.rotor_w_nm
        if self.friction is not None:
            coulomb, viscous = self.friction[0][sel], self.friction[1][sel]
            demand_speed = rotor_d + FRICTION_POSITION_GAIN_1_S * (rotor - theta[sel])
            ff = ff + coulomb * np.tanh(demand_speed / FRICTION_SMOOTH_RAD_S) + viscous * rotor_d
        return ff - np.einsum("ja,ja->j", self.k, error), ff

    def applied(self, tau_nm: np.ndarray, theta_d: np.ndarray) -> None:
        """The observer's prediction over the step the motors apply tau_nm (every joint's, after their limit) for;
        theta_d: the drive's speed at the step's start (the friction estimate's)."""
        sel, x = self.joints, self.state
        u = tau_nm[sel] + np.where(self.moving, self.held_rotor_nm, 0.0)   # the held rotor torque: an input while moving
        if self.friction is not None:
            u = u - friction_torque_nm(self.friction[0][sel], self.friction[1][sel], theta_d[sel], FRICTION_SMOOTH_RAD_S)
        ad = np.where(self.moving[:, None, None], self.ad, self.ad_m)
        x[:] = (np.einsum("jab,jb->ja", ad, x) + self.bd[:, :, 0] * u[:, None]
                + self.bd[:, :, 1] * self._link_other[:, None])
