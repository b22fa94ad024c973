"""The servo room's control law: per-joint P position and PI velocity loops on top of inverse-dynamics feed-forward."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from orc_rpl.robot.friction import friction_torque_nm
from orc_rpl.robot.model import ArmModel
from orc_rpl.errors import UsageError

# The ufuncs of the servo law as module names: update() runs a thousand times per simulated
# second, and `np.subtract` is two lookups where `subtract` is one.
add, subtract, multiply, minimum, maximum = np.add, np.subtract, np.multiply, np.minimum, np.maximum
not_equal, copyto, tanh = np.not_equal, np.copyto, np.tanh

#: Below this reference speed the Coulomb feed-forward fades out (tanh): no torque step at a reversal.
FRICTION_SMOOTH_RAD_S = 0.05


@dataclass(frozen=True, slots=True)
class ServoGains:
    """Loop tuning, the same for every joint: bandwidths, scaled per joint by its inertia at the current pose.

    Velocity loop: tau_fb = M_ii(q) * (velocity_bw * e_v + integral_bw * velocity_bw * integral of e_v),
    with e_v = qd_ref + position_gain * (q_ref - q) - qd. Scaling by the inertia keeps each joint's
    bandwidth the same whether the arm is folded or stretched (j1's inertia changes ten times).
    """

    position_gain_1_s: float = 40.0        #: P position loop: commanded speed per rad of error
    velocity_bw_rad_s: float = 160.0       #: P velocity loop bandwidth
    integral_bw_rad_s: float = 15.0        #: PI zero of the velocity loop (removes steady errors)
    integral_limit: float = 0.25           #: integral torque limited to this share of tau_max (anti-windup)
    inertia_every_steps: int = 4           #: recompute M_ii(q) every so many steps (a motion cycle)
    #: per-joint caps on the two bandwidths above (elastic gears: servo/two_mass.py), () for none
    joint_velocity_bw_rad_s: tuple[float, ...] = ()
    joint_position_gain_1_s: tuple[float, ...] = ()
    #: the elastic gears the caps were placed for (stiffness, and the rotor inertia at the joint), () for rigid
    #: gears: a tuning that knows the inertia at its pose places its bandwidths by them (CALIBRATE)
    gear_stiffness_nm_rad: tuple[float, ...] = ()
    rotor_inertia_kg_m2: tuple[float, ...] = ()

    def per_joint(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """(position gain, velocity bandwidth) of each of n joints: the scalars, capped by the per-joint values."""
        kp, bw = np.full(n, self.position_gain_1_s), np.full(n, self.velocity_bw_rad_s)
        for values, caps in ((kp, self.joint_position_gain_1_s), (bw, self.joint_velocity_bw_rad_s)):
            if caps:
                if len(caps) != n:
                    raise UsageError(f"per-joint servo gains are for {len(caps)} joints, the arm has {n}")
                np.minimum(values, np.array(caps, dtype=float), out=values)
        return kp, bw

    def __post_init__(self) -> None:
        for name in ("position_gain_1_s", "velocity_bw_rad_s", "integral_bw_rad_s", "integral_limit"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value >= 0.0):
                raise UsageError(f"servo gain {name} must be a finite number >= 0, got {value!r}")
        if self.inertia_every_steps < 1:
            raise UsageError(f"inertia_every_steps must be >= 1, got {self.inertia_every_steps}")


@dataclass(frozen=True, slots=True)
class ServoTuning:
    """A task-specific tuning (thesis 2.4, made by CALIBRATE): per-joint gains and feed-forward corrections.

    Used for one motion at a time (`JointServo.set_tuning`): the bandwidths replace `ServoGains`' (each
    still scaled by the model's M_ii(q)), and the feed-forward gets tau += d_inertia qdd_ref +
    d_viscous qd_ref + d_offset for what the model does not know (an unmodelled payload's inertia,
    friction, weight). `label` is how programs print it.
    """

    position_gain_1_s: tuple[float, ...]      #: P position loop, per joint
    velocity_bw_rad_s: tuple[float, ...]      #: P velocity loop bandwidth (relative to the model's M_ii)
    integral_bw_rad_s: tuple[float, ...]      #: PI zero of the velocity loop
    d_inertia_kg_m2: tuple[float, ...]        #: feed-forward: inertia the model lacks
    d_viscous_nm_s: tuple[float, ...]         #: feed-forward: viscous friction the model lacks
    d_offset_nm: tuple[float, ...]            #: feed-forward: constant torque the model lacks (weight)
    label: str = "tuning()"
    #: feed-forward: a mass at the flange the model lacks (kg), added to the model's payload while the tuning
    #: holds, so its weight, inertia and Coriolis torques are right at every pose of the motion
    load_kg: float = 0.0
    #: feed-forward: the model's nominal joint friction (Coulomb and viscous) times these, per joint, while the
    #: tuning holds (a cold gearbox's friction, as identified); () keeps the nominal friction
    friction_factor: tuple[float, ...] = ()
    #: the speed (rad/s) over which the Coulomb feed-forward's sign is smoothed on the joints under the state
    #: feedback for elastic gears while the tuning holds (as identified: how sharply the friction turns with the
    #: speed); 0 keeps FRICTION_SMOOTH_RAD_S
    friction_smooth_rad_s: float = 0.0

    def __post_init__(self) -> None:
        n = len(self.position_gain_1_s)
        for name in ("position_gain_1_s", "velocity_bw_rad_s", "integral_bw_rad_s", "d_inertia_kg_m2",
                     "d_viscous_nm_s", "d_offset_nm"):
            values = np.array(getattr(self, name), dtype=float)
            if values.shape != (n,) or not np.all(np.isfinite(values)):
                raise UsageError(f"tuning {name} must be {n} finite numbers, got {getattr(self, name)!r}")
            if name.endswith(("_1_s", "_rad_s")) and np.any(values < 0):
                raise UsageError(f"tuning {name} must be >= 0, got {getattr(self, name)!r}")
        if not (np.isfinite(self.load_kg) and self.load_kg >= 0.0):
            raise UsageError(f"tuning load_kg must be a finite mass >= 0, got {self.load_kg!r}")
        if not (np.isfinite(self.friction_smooth_rad_s) and self.friction_smooth_rad_s >= 0.0):
            raise UsageError(f"tuning friction_smooth_rad_s must be a finite speed >= 0, "
                             f"got {self.friction_smooth_rad_s!r}")
        factor = np.array(self.friction_factor, dtype=float)
        if factor.shape not in ((0,), (n,)) or not np.all(np.isfinite(factor)) or np.any(factor < 0):
            raise UsageError(f"tuning friction_factor must be {n} finite numbers >= 0 or none, got {self.friction_factor!r}")

    def __str__(self) -> str:
        return self.label


class JointServo:
    """Local control of all joints at the servo period; its attributes are the internal signals of the last cycle.

    `update` runs a thousand times per simulated second: it works in preallocated arrays with the
    output argument of numpy's ufuncs (no allocation, no attribute chains, no input checks: the
    loop checks a motion cycle's references once). The operations and their order are those of the
    plain formula in `ServoGains`, so the torques are the same to the last bit.
    """

    def __init__(self, arm: ArmModel, period_s: float = 0.001, gains: ServoGains = ServoGains()) -> None:
        self.arm = arm
        self.period_s = period_s
        self.gains = gains
        n = arm.n_joints
        self._tau_max = np.array(arm.tau_max)
        self._tau_min = -self._tau_max
        self._integral_max = gains.integral_limit * self._tau_max
        self._integral_min = -self._integral_max
        # gains at home until the first update schedules them at the measured pose
        kp, velocity_bw = gains.per_joint(n)
        self._kv = np.diag(arm.mass_matrix(arm.home_q)) * velocity_bw
        self._ki_dt = self._kv * (gains.integral_bw_rad_s * period_s)
        #: the model's inverse dynamics, (q, qd, qdd) -> tau: the servo's feed-forward, also read by the gears' observer
        #: and the state feedback (the same model, not a second one)
        self.inverse_dynamics = arm.inverse_dynamics_function()
        self._steps = 0
        self._inertia_every = gains.inertia_every_steps
        # Scalar gains as arrays: numpy multiplies two arrays faster than an array and a Python float,
        # and the products are the same numbers.
        self._kp = kp
        self._velocity_bw = velocity_bw
        self._integral_bw_dt = np.full(n, gains.integral_bw_rad_s * period_s)
        # Work arrays of update(); the integral alternates between two buffers (the anti-windup
        # needs last cycle's value while the new one is formed).
        self._work = np.zeros(n)
        self._demand = np.zeros(n)
        self._integral_next = np.zeros(n)
        # Internal signals (software sensors), overwritten in place each cycle; read them, do not keep them.
        self.position_error = np.zeros(n)     #: q_ref - q (rad)
        self.velocity_error = np.zeros(n)     #: qd_ref + position_gain * position_error - qd (rad/s)
        self.velocity = np.zeros(n)           #: measured qd (rad/s); the loop lends the plant's own (read-only) array
        self.torque = np.zeros(n)             #: commanded torque after saturation (N m): the torque estimate
        self.torque_ff = np.zeros(n)          #: inverse-dynamics feed-forward (N m)
        self.integral = np.zeros(n)           #: integral torque of the velocity loop (N m)
        self.saturated = np.zeros(n, dtype=bool)  #: joints whose demand exceeded tau_max
        # Set from above (thesis 5.3: "feed forward signals to torque references can be set"), e.g. by
        # a force controller; added to every cycle's demand until changed.
        self.torque_offset = np.zeros(n)      #: extra torque reference (N m)
        self.tuning: ServoTuning | None = None  #: the task-specific tuning in use (None: `gains`)
        self._d_inertia, self._d_viscous, self._d_offset = np.zeros(n), np.zeros(n), np.zeros(n)
        self._extra, self._extra_work = np.zeros(n), np.zeros(n)
        self._coulomb: np.ndarray | None = None   #: friction of the model in use (set_friction), None: none
        self._viscous: np.ndarray | None = None
        self._friction_nominal: tuple[np.ndarray, np.ndarray] | None = None  #: as set, before a tuning's factor
        self._control_load_kg = 0.0   #: the payload of the motion (its LOAD); a tuning's load_kg comes on top

    def set_control_payload(self, mass_kg: float) -> None:
        """The payload the feed-forward assumes (a motion's LOAD), plus the load of the tuning in use."""
        self._control_load_kg = float(mass_kg)
        self.arm.set_payload(self._control_load_kg + (self.tuning.load_kg if self.tuning is not None else 0.0))

    def reset(self) -> None:
        """Forget the integral and the signals (after a plant reset)."""
        n = self.arm.n_joints
        for signal in (self.position_error, self.velocity_error, self.torque, self.integral):
            signal[:] = 0.0
        # velocity may be the plant's own array, torque_ff the last RNEA result: rebind, never write into them
        self.velocity, self.torque_ff = np.zeros(n), np.zeros(n)
        self.saturated[:] = False
        self.torque_offset = np.zeros(n)
        self._steps = 0

    def set_tuning(self, tuning: ServoTuning | None, q: Any = None) -> None:
        """Use a task-specific tuning from the next cycle on (None: back to `gains`), without a bump.

        Bumpless: the integral gives up (or takes back) the constant torque the tuning's feed-forward
        adds, and the weight of its load at the measured pose `q` (no load change without q), so the
        total torque does not jump at the switch; the per-joint gains are rescheduled at the next
        cycle's pose. Without a tuning, `update` is the plain law, unchanged.
        """
        n, g = self.arm.n_joints, self.gains
        if tuning is None:
            (kp, bw), ibw = g.per_joint(n), np.full(n, g.integral_bw_rad_s)
            d_inertia, d_viscous, d_offset = np.zeros(n), np.zeros(n), np.zeros(n)
        else:
            if len(tuning.position_gain_1_s) != n:
                raise UsageError(f"the tuning is for {len(tuning.position_gain_1_s)} joints, the arm has {n}")
            kp, bw, ibw = (np.array(v, dtype=float) for v in (tuning.position_gain_1_s, tuning.velocity_bw_rad_s,
                                                               tuning.integral_bw_rad_s))
            d_inertia, d_viscous, d_offset = (np.array(v, dtype=float) for v in (tuning.d_inertia_kg_m2,
                                                                              tuning.d_viscous_nm_s, tuning.d_offset_nm))
        integral = self.integral + self._d_offset - d_offset
        load_kg = self._control_load_kg + (tuning.load_kg if tuning is not None else 0.0)
        if q is not None and load_kg != self.arm.payload[0]:
            q_now, zero = np.array(q, dtype=float), np.zeros(n)
            weight_before = np.array(self.inverse_dynamics(q_now, zero, zero))
            self.arm.set_payload(load_kg)
            integral -= np.array(self.inverse_dynamics(q_now, zero, zero)) - weight_before
        np.clip(integral, self._integral_min, self._integral_max, out=integral)
        self.integral = integral
        self._kp, self._velocity_bw, self._integral_bw_dt = kp, bw, ibw * self.period_s
        self._d_inertia, self._d_viscous, self._d_offset = d_inertia, d_viscous, d_offset
        self._steps = 0  # the next cycle schedules the gains at the measured pose
        self.tuning = tuning
        self._apply_friction()
        self._choose_law()

    def set_friction(self, coulomb_nm: Any = None, viscous_nm_s: Any = None) -> None:
        """The model's nominal joint friction, added to the feed-forward from the next cycle; None: none.

        tau += coulomb * tanh((qd_ref + position_gain * (q_ref - q)) / FRICTION_SMOOTH_RAD_S) + viscous * qd_ref:
        the speed the loop asks for, not the measured one (a noisy speed would chatter the Coulomb term).
        """
        n = self.arm.n_joints
        if coulomb_nm is None and viscous_nm_s is None:
            self._friction_nominal = None
        else:
            fc, fv = (np.zeros(n) if v is None else np.array(v, dtype=float).reshape(-1) for v in (coulomb_nm, viscous_nm_s))
            if fc.shape != (n,) or fv.shape != (n,) or not (np.all(np.isfinite(fc)) and np.all(np.isfinite(fv))):
                raise UsageError(f"friction must be {n} finite Coulomb and {n} viscous values")
            self._friction_nominal = (fc, fv)
        self._apply_friction()
        self._choose_law()

    def friction(self) -> tuple[np.ndarray, np.ndarray] | None:
        """The model's nominal joint friction (Coulomb N m, viscous N m s/rad) as set, or None."""
        return self._friction_nominal

    def friction_in_use(self) -> tuple[np.ndarray, np.ndarray] | None:
        """The friction the feed-forward uses now (Coulomb N m, viscous N m s/rad; a tuning's factor included), or None."""
        if self._coulomb is None or self._viscous is None:
            return None
        return self._coulomb, self._viscous

    def _apply_friction(self) -> None:
        """The friction in use: the nominal one, times the factor of the tuning in use."""
        nominal, tuning = self._friction_nominal, self.tuning
        if nominal is None:
            self._coulomb = self._viscous = None
            return
        factor = np.array(tuning.friction_factor, dtype=float) if tuning is not None and tuning.friction_factor else 1.0
        self._coulomb, self._viscous = nominal[0] * factor, nominal[1] * factor

    def model_torque(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
        """The model's torque for a motion state: rigid-body dynamics with the control payload, plus nominal friction."""
        tau = np.array(self.inverse_dynamics(q, qd, qdd))
        friction = self.model_friction(qd)
        if friction is not None:
            tau += friction
        return tau

    def model_friction(self, qd: np.ndarray) -> np.ndarray | None:
        """The model's friction torque at speeds qd (one state, or (k, n) rows), or None: the model has none."""
        if self._coulomb is None:
            return None
        return friction_torque_nm(self._coulomb, self._viscous, qd, FRICTION_SMOOTH_RAD_S)

    def _choose_law(self) -> None:
        """The plain law unless a tuning or friction adds feed-forward terms."""
        if self.tuning is None and self._coulomb is None:
            self.__dict__.pop("update", None)  # the plain law again
        else:
            self.update = self._update_tuned  # type: ignore[method-assign]

    def _update_tuned(self, q_ref: np.ndarray, qd_ref: np.ndarray, qdd_ref: np.ndarray,
                      q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """`update` with the tuning's and the friction's feed-forward added to the torque offset for this cycle."""
        extra, work, offset = self._extra, self._extra_work, self.torque_offset
        if self.tuning is not None:
            multiply(self._d_inertia, qdd_ref, extra)
            multiply(self._d_viscous, qd_ref, work)
            add(extra, work, extra)
            add(extra, self._d_offset, extra)
        else:
            extra.fill(0.0)
        if self._coulomb is not None:
            # the speed the loop asks for (reference plus position correction): a joint stuck short of
            # its target still gets the Coulomb torque in the right direction
            subtract(q_ref, q, work)
            multiply(work, self._kp, work)
            add(work, qd_ref, work)
            multiply(work, 1.0 / FRICTION_SMOOTH_RAD_S, work)
            tanh(work, work)
            multiply(work, self._coulomb, work)
            add(extra, work, extra)
            multiply(qd_ref, self._viscous, work)
            add(extra, work, extra)
        add(extra, offset, extra)
        self.torque_offset = extra
        try:
            return JointServo.update(self, q_ref, qd_ref, qdd_ref, q, qd)
        finally:
            self.torque_offset = offset

    def update(self, q_ref: np.ndarray, qd_ref: np.ndarray, qdd_ref: np.ndarray,
               q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """One servo cycle: the torque to apply for the next period (unchecked inputs: the loop checks once).

        The result is the `torque` signal itself: apply or copy it before the next update.
        """
        kv, ki_dt = self._kv, self._ki_dt
        steps = self._steps
        if steps % self._inertia_every == 0:
            multiply(self.arm.mass_matrix_diagonal_unchecked(q), self._velocity_bw, kv)
            multiply(kv, self._integral_bw_dt, ki_dt)
        self._steps = steps + 1
        error, velocity_error, work = self.position_error, self.velocity_error, self._work
        subtract(q_ref, q, error)
        subtract(qd_ref, qd, velocity_error)
        multiply(error, self._kp, work)
        add(velocity_error, work, velocity_error)
        integral, last_integral = self._integral_next, self.integral
        multiply(ki_dt, velocity_error, work)
        add(last_integral, work, integral)
        # out= by keyword: numpy 2.4 takes a slow path for minimum/maximum with a positional out (5x)
        minimum(integral, self._integral_max, out=integral)
        maximum(integral, self._integral_min, out=integral)
        tau_ff = self.inverse_dynamics(q_ref, qd_ref, qdd_ref)
        demand, tau, saturated = self._demand, self.torque, self.saturated
        multiply(kv, velocity_error, demand)
        add(demand, tau_ff, demand)
        add(demand, integral, demand)
        add(demand, self.torque_offset, demand)
        minimum(demand, self._tau_max, out=tau)
        maximum(tau, self._tau_min, out=tau)
        not_equal(tau, demand, saturated)
        if True in saturated.tolist():  # half the time of count_nonzero on six flags
            # Anti-windup: do not integrate further into a saturated motor.
            copyto(integral, last_integral, where=saturated)
        self.integral, self._integral_next = integral, last_integral
        self.velocity = qd
        self.torque_ff = tau_ff
        return tau
