"""The servo room's state feedback for elastic gears: per-joint LQR on the two-mass model with a Kalman observer, every 1 ms step."""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.linalg

from orc_rpl.plant import compiled
from orc_rpl.robot.friction import friction_torque_nm
from orc_rpl.robot.model import ArmModel
from orc_rpl.servo.control import FRICTION_SMOOTH_RAD_S
from orc_rpl.servo.state_feedback_layout import FLAGS_SIZE, KEPT, SCHEDULED, SETTLING, SOLVED, law_size, law_views

#: The closed-loop bandwidth (rad/s) of each joint's link position: the LQR's link poles sit there (damping
#: about 0.8), above the anti-resonance where the cascade had to stay below it (j1 38, j2 48 rad/s).
LINK_BANDWIDTH_RAD_S = 80.0
#: The LQR's weight on the motor's angle and speed errors, as a share of the link's (the rotor's own mode is
#: damped through them; the link's error is what the tool shows).
MOTOR_WEIGHT = 1.0
#: Riccati iterations (the LQR's and the Kalman filter's) per motion cycle on the model of the pose then, from the
#: last cycle's solutions: the gains follow the pose (the filter's, one iteration a step, is the time-varying one).
RICCATI_ITERATIONS = 4
#: The Kalman observer's assumptions (1 sigma): torques on the rotor and on the link the model does not know,
#: as white noise (N m sqrt(s)), the link's unknown torque as a random walk (N m / sqrt(s)), the encoder's angle
#: (rad) and the drive's speed measurement (rad/s).
ROTOR_NOISE_NM = 50.0
LINK_NOISE_NM = 2.0
DISTURBANCE_WALK_NM = 400.0
#: The same for a joint at rest, its unknown torque on the rotor (static friction): slower, or the rotor hunts
#: (stick-slip) after a move: swings of the links of 0.12 mrad with 400, 0.003 with 100 (short moves, zones).
REST_WALK_NM = 100.0
ANGLE_NOISE_RAD = 1e-4
SPEED_NOISE_RAD_S = 2e-2
#: A joint's reference moving faster than this (rad/s): the observer's unknown torque is the link's (an undeclared
#: payload's, passing through the gear and twisting it); slower, the rotor's (at rest the motor side cannot tell the
#: rotor's static friction from the link's torque, and the friction acts on the rotor). As GearTwist's hold.
MOVING_RAD_S = 0.2

#: When a joint starts to move, this share of the unknown torque it learnt at rest (on the rotor) becomes the link's:
#: at rest the motor side cannot tell the rotor's static friction from an undeclared payload's weight, and the move
#: would otherwise start with none of the payload in the gear's twist. bench_arm_control's moves, links: 0, 0.3, 0.5,
#: 0.7, 1 gave 1.423, 0.995, 0.811, 0.859, 0.908 mm (the encoders 0.460 every time; saturated 0.0016 to 0.0057).
REST_TORQUE_TO_LINK = 0.5

#: The model and gains are made again at a motion cycle only when the links' inertia matrix has moved by more than this
#: share since they were made (any entry, over sqrt(M_ii M_jj)), a joint started or stopped moving, or the last Riccati
#: iterations still moved the gains (k or l) by more than GAINS_SETTLED of their largest entry; otherwise the steps
#: keep them (the schedule cost some 60 us a 4 ms cycle, more than the rest of the servo and plant together).
#: (This and the schedule's other constants are read when a law is made: set them before.)
INERTIA_TOLERANCE = 0.02
GAINS_SETTLED = 3e-2

#: Joints whose anti-resonance at the links' largest inertia is above this (rad/s) keep the cascade (servo/control.py)
#: on the twisted references: the rigid tuning's velocity loop is below their anti-resonance anyway (two_mass.py).
STATE_FEEDBACK_BELOW_RAD_S = 160.0

#: The speed (per rad of the rotor's error) added to the reference's for the sign of the Coulomb feed-forward,
#: as the cascade's position gain does it: a rotor stuck short of its target gets its friction fed forward.
FRICTION_POSITION_GAIN_1_S = 40.0


def slow_joints_model(rotor_kg_m2: np.ndarray, link_inertia: np.ndarray, stiffness_nm_rad: np.ndarray,
                      damping_nm_s: np.ndarray, on_link: np.ndarray, period_s: float) -> tuple[np.ndarray, np.ndarray]:
    """The slow joints' two-mass model, their links coupled, sampled with the torques held over each period.

    State blocks (m joints each): the rotors' angles theta and speeds, the links' q and speeds, and an
    unknown torque w per joint (constant in the model), on the link where `on_link`, else on the rotor.
    Inputs: the motors' torques u less the rotors' friction, and b, the links' torques other than their
    inertia's (gravity, Coriolis, the other joints' accelerations):
    J_r theta'' = u - K (theta - q) - D (theta' - q') [+ w],  M_l q'' = K (theta - q) + D (theta' - q') - b [+ w],
    M_l the model's inertia matrix of the slow joints less the rotors (`link_inertia`).
    """
    m = len(rotor_kg_m2)
    k, d, inv_rotor = np.diag(stiffness_nm_rad), np.diag(damping_nm_s), np.diag(1.0 / rotor_kg_m2)
    inv_link = np.linalg.inv(link_inertia)
    t, td, q, qd, w = (slice(i * m, (i + 1) * m) for i in range(5))
    a = np.zeros((7 * m, 7 * m))   # [A B; 0 0]: its exponential holds (Ad, Bd)
    a[t, td] = a[q, qd] = np.eye(m)
    a[td, t], a[td, td], a[td, q], a[td, qd] = -inv_rotor @ k, -inv_rotor @ d, inv_rotor @ k, inv_rotor @ d
    a[qd, t], a[qd, td], a[qd, q], a[qd, qd] = inv_link @ k, inv_link @ d, -inv_link @ k, -inv_link @ d
    a[qd, w] = inv_link * on_link[None, :]
    a[td, w] = inv_rotor * ~on_link[None, :]
    a[td, 5 * m : 6 * m], a[qd, 6 * m :] = inv_rotor, -inv_link
    e = _expm(a * period_s)
    return e[: 5 * m, : 5 * m], e[: 5 * m, 5 * m :]


#: Terms of the series of the sampled model's exponential.
EXPM_TERMS = 8


def _expm(a: np.ndarray, terms: int = EXPM_TERMS) -> np.ndarray:
    """exp(a) by its series (a: a sampled model, |a| well below 1 per step: the terms fall fast)."""
    result, term = np.eye(len(a)), np.eye(len(a))
    for i in range(1, terms + 1):
        term = term @ a / i
        result = result + term
    return result


def lqr_weights(rotor_kg_m2: np.ndarray, link_inertia: np.ndarray, bandwidth_rad_s: float) -> np.ndarray:
    """The LQR's state weights on (theta, theta', q, q') errors: per joint a double integrator's of its whole inertia
    J (weights (J w^2)^2 on the angle and 1 on the torque put its poles at w, damping 0.7), on the link, and
    MOTOR_WEIGHT of it on the rotor."""
    j, w = rotor_kg_m2 + np.diag(link_inertia), bandwidth_rad_s
    angle, speed = (j * w * w) ** 2, 0.5 * (j * w) ** 2
    return np.diag(np.concatenate([MOTOR_WEIGHT * angle, MOTOR_WEIGHT * speed, angle, speed]))


def noise_covariances(rotor_kg_m2: np.ndarray, link_inertia: np.ndarray, moving: np.ndarray,
                      period_s: float) -> tuple[np.ndarray, np.ndarray]:
    """The Kalman filter's process noise (per step) and measurement noise covariances (the angles, then the speeds);
    `moving`: the joints whose unknown torque is the link's (the others' walks at REST_WALK_NM)."""
    m = len(rotor_kg_m2)
    process = np.concatenate([np.zeros(m), (ROTOR_NOISE_NM / rotor_kg_m2) ** 2, np.zeros(m),
                              (LINK_NOISE_NM / np.diag(link_inertia)) ** 2,
                              np.where(moving, DISTURBANCE_WALK_NM, REST_WALK_NM) ** 2])
    measurement = np.concatenate([np.full(m, ANGLE_NOISE_RAD ** 2), np.full(m, SPEED_NOISE_RAD_S ** 2)])
    return np.diag(process) * period_s, np.diag(measurement)


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
    """State feedback for joints whose gear is a spring: the torques from the rotors' and the links' states.

    The slow joints (anti-resonance below STATE_FEEDBACK_BELOW_RAD_S: `joints`) are one two-mass system
    (`slow_joints_model`) whose link inertia matrix the model computes for the pose (its block of M(q)
    less the rotors, every `schedule`: the links are coupled, j2's and j3's strongly). The rotors'
    references lead the links' by the twist the link torque needs (the model's, less the observer's
    unknown link torque); the feed-forward is the model's torque, its friction estimate, and less the
    unknown torques; the feedback is an LQR's gain on the errors of the rotors' angles and speeds and of
    the links', the links' as a Kalman filter estimates them from the encoders and the drives' speeds
    every 1 ms step. The unknown torques are the integral action: while a joint's reference moves, the
    one the filter follows is the link's (an undeclared payload: it passes through the gear and twists
    it), at rest the rotor's (there the motor side cannot tell static friction from link torque); the
    other is held, and as a joint starts to move REST_TORQUE_TO_LINK of what it learnt at rest goes to the link. Designed from the controller's model (nominal stiffness, damping and inertias),
    nothing of the plant's own parameters. The other joints' rotors get the twist of the model's link
    torque (`twist_rad`) and keep the cascade (ServoLoop runs it).
    """

    def __init__(self, arm: ArmModel, rotor_kg_m2: Any, stiffness_nm_rad: Any, damping_nm_s: Any, period_s: float,
                 bandwidth_rad_s: float | None = None, joints: Any = None) -> None:
        """bandwidth_rad_s: the links' closed-loop bandwidth (None: LINK_BANDWIDTH_RAD_S); joints: the indices of
        the joints under state feedback (None: those whose anti-resonance is below STATE_FEEDBACK_BELOW_RAD_S)."""
        self.arm, self.period_s = arm, float(period_s)
        self.bandwidth_rad_s = LINK_BANDWIDTH_RAD_S if bandwidth_rad_s is None else float(bandwidth_rad_s)
        n = arm.n_joints
        rotor = np.asarray(rotor_kg_m2, dtype=float)
        stiffness = np.asarray(stiffness_nm_rad, dtype=float)
        _, high = link_inertia_range(arm, rotor)
        #: the joints under state feedback (the slow gears), the others' indices in `cascade`
        self.joints = (np.flatnonzero(np.sqrt(stiffness / high) < STATE_FEEDBACK_BELOW_RAD_S) if joints is None
                       else np.array(joints, dtype=int))
        self.cascade = np.setdiff1d(np.arange(n), self.joints)
        sel = self.joints
        m = self.m = len(sel)
        # Every float array the law keeps is a view of one buffer (servo/state_feedback_layout.py: a compiled motion
        # cycle takes the law as one argument); they are written in place, never rebound.
        self._buffer = np.zeros(law_size(n, m))
        (self.twist_rad,        #: the twist of the last row commanded, every joint (rad)
         self.rotor_all, self.stiffness_all,
         self.held_link_nm, self.held_rotor_nm, self._link_other,
         self.rotor, self.stiffness, self.damping, self.tau_max,
         self.state,            #: the filter's (theta, theta', q, q', w) blocks of the slow joints
         self.link_inertia,     #: the links' inertia matrix the model and gains were made for
         self.k, self.l,        #: the gains (`schedule` makes them)
         self.ad, self.bd, self._weights, self._process, self._measurement,
         self._p, self._s,      # the LQR's Riccati solution, the filter's prior covariance
         self._inertia_now, self._k_before, self._l_before) = law_views(self._buffer, n, m)
        self.rotor_all[:], self.stiffness_all[:] = rotor, stiffness
        self.rotor[:], self.stiffness[:] = rotor[sel], stiffness[sel]
        self.damping[:] = np.asarray(damping_nm_s, dtype=float)[sel]
        self.tau_max[:] = np.array(arm.tau_max, dtype=float)[sel]
        self.link_inertia[:] = np.eye(m)
        #: solved, settling (the last schedule's iterations still moved the gains by more than GAINS_SETTLED), and
        #: the counts of motion cycles whose schedule made the gains again and kept them (`state_feedback_layout`)
        self._flags = np.zeros(FLAGS_SIZE, dtype=np.int64)
        self._flags[SETTLING] = 1
        self.c = np.zeros((2 * m, 5 * m))   # the filter measures the rotors' angles and speeds
        self.c[:, : 2 * m] = np.eye(2 * m)
        self.friction: tuple[np.ndarray, np.ndarray] | None = None   #: the rotors' friction estimate (all joints)
        #: per slow joint: True while its reference moves faster than MOVING_RAD_S (the filter's w is then the
        #: link's unknown torque, the rotor's held), False at rest (w the rotor's, the link's held)
        self.moving = np.zeros(m, dtype=bool)
        self._no_friction = np.zeros(n)
        #: the speed over which the Coulomb feed-forward's and the filter's friction sign is smoothed (a tuning's:
        #: `set_friction_smooth`)
        self.friction_smooth_rad_s = FRICTION_SMOOTH_RAD_S
        self._no_speeds = np.zeros(n)
        # the schedule's constants as the module has them when the law is made (the compiled schedule's `_tuning` too)
        self._iterations, self._moving_rad_s, self._rest_to_link = RICCATI_ITERATIONS, MOVING_RAD_S, REST_TORQUE_TO_LINK
        self._inertia_tolerance, self._gains_settled = INERTIA_TOLERANCE, GAINS_SETTLED
        self._work = np.empty(max(n, 7 * m))   # the compiled step's scratch
        #: the compiled schedule (servo/state_feedback_kernels.py), None where numba is not; `compiled.ON` picks
        self._kernels: Any = compiled.kernels("orc_rpl.servo.state_feedback_kernels")
        if self._kernels is not None:   # the design's constants, as the kernels read them (when the law is made)
            kernels = self._kernels
            self._tuning = np.zeros(kernels.TUNING_SIZE)
            self._tuning[[kernels.BANDWIDTH, kernels.MOTOR_WEIGHT, kernels.ROTOR_NOISE, kernels.LINK_NOISE, kernels.WALK,
                          kernels.REST_WALK, kernels.ANGLE_NOISE, kernels.SPEED_NOISE, kernels.PERIOD, kernels.EXPM_TERMS,
                          kernels.FRICTION_GAIN, kernels.FRICTION_SMOOTH, kernels.INERTIA_TOLERANCE,
                          kernels.GAINS_SETTLED, kernels.MOVING, kernels.REST_TO_LINK, kernels.ITERATIONS]] = (
                self.bandwidth_rad_s, MOTOR_WEIGHT, ROTOR_NOISE_NM, LINK_NOISE_NM, DISTURBANCE_WALK_NM, REST_WALK_NM,
                ANGLE_NOISE_RAD, SPEED_NOISE_RAD_S, self.period_s, EXPM_TERMS, FRICTION_POSITION_GAIN_1_S,
                self.friction_smooth_rad_s, self._inertia_tolerance, self._gains_settled, self._moving_rad_s,
                self._rest_to_link, self._iterations)

    @property
    def scheduled(self) -> int:
        """Motion cycles whose schedule made the gains again."""
        return int(self._flags[SCHEDULED])

    @property
    def kept(self) -> int:
        """Motion cycles whose schedule kept the gains."""
        return int(self._flags[KEPT])

    @property
    def solved(self) -> bool:
        """The Riccati equations have been solved (since the last `reset`): the schedule iterates from their solutions."""
        return bool(self._flags[SOLVED])

    def schedule(self, q: np.ndarray, qd_ref: np.ndarray | None = None, iterations: int | None = None) -> None:
        """The model at pose q (the links' inertia matrix from the model's M(q)) and for the reference speeds qd_ref
        (every joint's; which side each unknown torque is on: `switch`), and the gains for it: a few Riccati
        iterations from the last solutions (`iterations`, None: RICCATI_ITERATIONS; 0: solved anew). With
        `iterations` None the model and gains are kept while the inertia has moved less than INERTIA_TOLERANCE
        since they were made, no joint started or stopped, and the last iterations had settled (GAINS_SETTLED)."""
        flags = self._flags
        if iterations is None and qd_ref is not None and self._kernels is not None and compiled.ON and flags[SOLVED]:
            body = self.arm.rigid_body_rows()   # the model's rows for the compiled M(q) (None: Pinocchio's)
            if body is not None:   # all of it compiled (the rest is its reference)
                self._kernels.law_schedule(body, q, qd_ref, self.joints, self._buffer, self.moving, flags, self._tuning)
                return
        inertia, moved, moving = self._link_inertia_at(q, qd_ref)
        switched = moving is not None and self.switch(moving)
        remodel = iterations is not None or not flags[SOLVED] or switched or moved > self._inertia_tolerance
        if not (remodel or flags[SETTLING]):
            flags[KEPT] += 1
            return
        self._k_before[:], self._l_before[:] = self.k, self.l
        count = self._iterations if iterations is None else iterations
        compiled_now = self._kernels is not None and compiled.ON and bool(flags[SOLVED]) and count > 0
        if remodel:   # else the iterations go on for the model they were started on (the inertia has not moved)
            self.link_inertia[:] = inertia
            self._model(compiled_now)
        if compiled_now:
            self._kernels.riccati_gains(self.ad, self.bd, self._weights, self._process, self._measurement, count,
                                        self._p, self._s, self.k, self.l)
        else:
            self._iterate_numpy(count)
        flags[SCHEDULED] += 1
        change = max(np.max(np.abs(self.k - self._k_before)) / np.max(np.abs(self.k)),
                     np.max(np.abs(self.l - self._l_before)) / np.max(np.abs(self.l)))
        flags[SETTLING] = change > self._gains_settled

    def _model(self, compiled_now: bool) -> None:
        """The sampled model, the LQR's weights and the filter's noises for self.link_inertia and self.moving."""
        if compiled_now:   # servo/state_feedback_kernels.py: the same, compiled
            self._kernels.sampled_model(self.link_inertia, self.rotor, self.stiffness, self.damping, self.moving,
                                        self._tuning, self.ad, self.bd, self._weights, self._process, self._measurement)
            return
        self.ad[:], self.bd[:] = slow_joints_model(self.rotor, self.link_inertia, self.stiffness, self.damping,
                                                   self.moving, self.period_s)
        self._weights[:] = lqr_weights(self.rotor, self.link_inertia, self.bandwidth_rad_s)
        self._process[:], self._measurement[:] = noise_covariances(self.rotor, self.link_inertia, self.moving,
                                                                   self.period_s)

    def _iterate_numpy(self, count: int) -> None:
        """`count` Riccati iterations from the last solutions on the model (0: solved anew), and the gains; numpy."""
        m = self.m
        a4, b4 = self.ad[: 4 * m, : 4 * m], self.bd[: 4 * m, :m]
        weights, process, measurement = self._weights, self._process, self._measurement
        r, a, c = np.eye(m), self.ad, self.c
        if not self._flags[SOLVED] or count == 0:
            self._p[:] = scipy.linalg.solve_discrete_are(a4, b4, weights, r)
            self._s[:] = scipy.linalg.solve_discrete_are(a.T, c.T, process, measurement)
            self._flags[SOLVED] = 1
        p, s = self._p.copy(), self._s.copy()
        for _ in range(count):
            bp = b4.T @ p
            gain = np.linalg.solve(r + bp @ b4, bp @ a4)
            p = weights + a4.T @ p @ (a4 - b4 @ gain)
            innovation = c @ s @ c.T + measurement
            s = a @ (s - s @ c.T @ np.linalg.solve(innovation, c @ s)) @ a.T + process
        self._p[:], self._s[:] = p, s
        bp = b4.T @ p
        self.k[:] = np.linalg.solve(r + bp @ b4, bp @ a4)                         # the LQR's gain (m x 4m)
        self.l[:] = s @ c.T @ np.linalg.inv(c @ s @ c.T + measurement)           # the filter's correction (5m x 2m)

    def _link_inertia_at(self, q: np.ndarray, qd_ref: np.ndarray | None) -> tuple[np.ndarray, float, Any]:
        """The links' inertia matrix at q (the slow joints' block of the model's M(q) less the rotors), how far it has
        moved from the one the gains were made for (its largest change over sqrt(M_ii M_jj) of the latter), and the
        slow joints moving at the reference speeds qd_ref (None: no change; with the kernels, None too when the
        flags are the same as `moving`'s)."""
        sel, arm = self.joints, self.arm
        if self._kernels is not None and compiled.ON:
            body = arm.rigid_body_rows()   # the model's rows for the compiled M(q) (None: Pinocchio's)
            if body is not None:   # compiled (servo/rnea_kernel.py): a new array each cycle, as Pinocchio's
                inertia, moving = np.empty((self.m, self.m)), np.empty(self.m, dtype=bool)
                speeds = self._no_speeds if qd_ref is None else qd_ref
                moved, changed = self._kernels.link_inertia_at(body, q, sel, self.rotor, self.link_inertia,
                                                               inertia, speeds, self._moving_rad_s, self.moving, moving)
                return inertia, moved, (moving if changed and qd_ref is not None else None)
        payload = arm.payload   # (kg, com): the model keeps its payload
        inertia = arm.mass_matrix(q, payload[0], payload[1:])[np.ix_(sel, sel)] - np.diag(self.rotor)
        scale = np.sqrt(np.outer(np.diag(self.link_inertia), np.diag(self.link_inertia)))
        moving = None if qd_ref is None else np.abs(np.asarray(qd_ref)[sel]) > self._moving_rad_s
        return inertia, float(np.max(np.abs(inertia - self.link_inertia) / scale)), moving

    def reset(self, q_link: np.ndarray, link_torque_nm: np.ndarray) -> None:
        """At rest, the links at q_link carrying link_torque_nm (the model's weight): the rotors ahead by the twist."""
        q_link, m = np.asarray(q_link, dtype=float), self.m
        self.moving[:] = False
        self.held_link_nm[:] = self.held_rotor_nm[:] = 0.0
        self._flags[SOLVED] = 0
        self.schedule(q_link, None, 0)
        self.twist_rad[:] = np.asarray(link_torque_nm, dtype=float) / self.stiffness_all
        sel, x = self.joints, self.state
        x[:] = 0.0
        x[:m], x[2 * m : 3 * m] = q_link[sel] + self.twist_rad[sel], q_link[sel]

    hold = reset   #: the name ServoLoop.reset calls a twist's (at rest, the rotors ahead of the links by it)

    @property
    def link_w_nm(self) -> np.ndarray:
        """The slow joints' unknown link torque w (N m; the model's link torque less it is the gear's)."""
        return np.where(self.moving, self.state[4 * self.m :], self.held_link_nm)

    @property
    def rotor_w_nm(self) -> np.ndarray:
        """The slow joints' unknown torque on the rotor (N m; the motor's torque less it drives the rotor)."""
        return np.where(self.moving, self.held_rotor_nm, self.state[4 * self.m :])

    @property
    def unknown_torque_nm(self) -> np.ndarray:
        """The slow joints' torque the model lacks, as the filter estimates it (N m, added to the model's)."""
        return -(self.link_w_nm + self.rotor_w_nm)

    def model_changed(self, torque_nm: np.ndarray) -> None:
        """The model's link torque changed by torque_nm (every joint's; a tuning's load at the measured pose): what
        the unknown link torques held of it is now the model's. The link side takes it (the followed w where a joint
        moves, the held one at rest), so the twist and the torque do not jump and the filter does not learn twice a
        weight the model now has (a CALIBRATE tuning's identified load: ServoLoop.set_tuning)."""
        change = np.asarray(torque_nm, dtype=float)[self.joints]
        w = self.state[4 * self.m :]
        w[self.moving] += change[self.moving]
        self.held_link_nm[~self.moving] += change[~self.moving]

    def set_friction_smooth(self, speed_rad_s: float | None) -> None:
        """Smooth the rotors' Coulomb friction sign over speed_rad_s (a tuning's identified sharpness; None or 0:
        FRICTION_SMOOTH_RAD_S again), in the feed-forward and in the filter's prediction. The servo's smoothing is
        broader than the gears' friction turns: over the slow end of a move its Coulomb term faded while the
        rotors' friction held, the filter learnt the difference and pushed the rotors past their target with it
        once they stuck (docs/assembly.md)."""
        self.friction_smooth_rad_s = float(speed_rad_s) if speed_rad_s else FRICTION_SMOOTH_RAD_S
        if self._kernels is not None:
            self._tuning[self._kernels.FRICTION_SMOOTH] = self.friction_smooth_rad_s

    def switch(self, moving: np.ndarray) -> bool:
        """Joints whose reference starts or stops moving: w changes sides, the other side's held (a start takes
        REST_TORQUE_TO_LINK of the rest's w to the link). True on a change (the model changes: `schedule` again)."""
        change = moving != self.moving
        if not change.any():
            return False
        w = self.state[4 * self.m :]
        start, stop = change & moving, change & ~moving
        rest = w[start].copy()
        share = self._rest_to_link
        self.held_rotor_nm[start], w[start] = (1.0 - share) * rest, self.held_link_nm[start] + share * rest
        self.held_link_nm[stop], w[stop] = w[stop], self.held_rotor_nm[stop]
        self.moving[:] = moving
        return True

    def references(self, q_ref: np.ndarray, qd_ref: np.ndarray, qdd_ref: np.ndarray,
                   tau_ff: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The rotors' reference angles and speeds for one row of link references (every joint): the link's plus
        the twist of the link torque (the slow joints' less the unknown link torque), its rate from the last row's."""
        if self._kernels is not None and compiled.ON:   # the same, compiled
            theta_ref, theta_d_ref = np.empty(len(q_ref)), np.empty(len(q_ref))
            self._kernels.law_references(q_ref, qd_ref, qdd_ref, tau_ff, self.joints, self.rotor_all, self.stiffness_all,
                                         self.state, self.moving, self.held_link_nm, self.link_inertia, self._tuning,
                                         self.twist_rad, self._link_other, theta_ref, theta_d_ref, self._work)
            return theta_ref, theta_d_ref
        sel = self.joints
        link_torque = tau_ff - self.rotor_all * qdd_ref
        w_link = self.link_w_nm
        link_torque[sel] -= w_link
        twist = link_torque / self.stiffness_all
        rate = (twist - self.twist_rad) / self.period_s
        self.twist_rad[:] = twist
        # the links' torque other than their inertia's; the held unknown torque at rest is an input then
        self._link_other[:] = link_torque[sel] + np.where(self.moving, w_link, 0.0) - self.link_inertia @ qdd_ref[sel]
        return q_ref + twist, qd_ref + rate

    def update(self, q_ref: np.ndarray, qd_ref: np.ndarray, theta_ref: np.ndarray, theta_d_ref: np.ndarray,
               tau_ff: np.ndarray, theta: np.ndarray, theta_d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """One 1 ms step of the slow joints (call `references` first, `applied` after): the demanded motor torques
        (before the drives' limits) and their feed-forward. Arguments are every joint's: the link's and the
        rotor's reference rows, the model's torque of the link reference (the rotor's inertia included), and
        the encoders' angles and the drives' speeds now."""
        if self._kernels is not None and compiled.ON:   # the same, compiled
            demand, ff = np.empty(self.m), np.empty(self.m)
            coulomb, viscous = self._friction_rows()
            self._kernels.law_update(q_ref, qd_ref, theta_ref, theta_d_ref, tau_ff, theta, theta_d, self.joints, self.state,
                                     self.l, self.k, self.moving, self.held_link_nm, self.held_rotor_nm,
                                     self.friction is not None, coulomb, viscous, self._tuning, demand, ff, self._work)
            return demand, ff
        sel, x, m = self.joints, self.state, self.m
        x += self.l @ (np.concatenate([theta[sel], theta_d[sel]]) - x[: 2 * m])
        reference = np.concatenate([theta_ref[sel], theta_d_ref[sel], q_ref[sel], qd_ref[sel]])
        ff = tau_ff[sel] - self.link_w_nm - self.rotor_w_nm
        if self.friction is not None:
            rotor, rotor_d = theta_ref[sel], theta_d_ref[sel]
            demand_speed = rotor_d + FRICTION_POSITION_GAIN_1_S * (rotor - theta[sel])
            ff = ff + self.friction[0][sel] * np.tanh(demand_speed / self.friction_smooth_rad_s) + self.friction[1][sel] * rotor_d
        return ff - self.k @ (x[: 4 * m] - reference), ff

    def applied(self, tau_nm: np.ndarray, theta_d: np.ndarray) -> None:
        """The filter's prediction over the step the motors apply tau_nm (every joint's, after their limit) for;
        theta_d: the drives' speeds at the step's start (the friction estimate's)."""
        if self._kernels is not None and compiled.ON:   # the same, compiled
            coulomb, viscous = self._friction_rows()
            self._kernels.law_predict(tau_nm, theta_d, self.joints, self.state, self.ad, self.bd, self.moving,
                                      self.held_rotor_nm, self._link_other, self.friction is not None, coulomb, viscous,
                                      self._tuning, self._work)
            return
        sel = self.joints
        u = tau_nm[sel] + np.where(self.moving, self.held_rotor_nm, 0.0)   # the held rotor torque: an input while moving
        if self.friction is not None:
            u = u - friction_torque_nm(self.friction[0][sel], self.friction[1][sel], theta_d[sel], self.friction_smooth_rad_s)
        self.state[:] = self.ad @ self.state + self.bd @ np.concatenate([u, self._link_other])

    def _friction_rows(self) -> tuple[np.ndarray, np.ndarray]:
        """The friction estimate's Coulomb and viscous rows (every joint) for the kernels; zeros where there is none."""
        if self.friction is None:
            return self._no_friction, self._no_friction
        return np.asarray(self.friction[0], dtype=float), np.asarray(self.friction[1], dtype=float)
