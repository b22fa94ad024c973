"""The servo room's seam to the motion layer: model, plant and servo advanced together, n servo steps per call."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from orc_rpl.robot.model import ArmModel, load_robot
from orc_rpl.errors import UsageError
from orc_rpl.plant import compiled
from orc_rpl.plant.sim import SimCell
from orc_rpl.servo.control import JointServo, ServoGains, ServoTuning
from orc_rpl.servo.drive import CompiledDrives
from orc_rpl.servo.state_feedback_cycle import StateFeedbackCycle
from orc_rpl.signals.logger import Logger


@dataclass(frozen=True, slots=True)
class ServoState:
    """What the loop measured at the end of a call (copies: safe to keep)."""

    time_s: float                 #: plant time
    q: np.ndarray                 #: joint angles (rad)
    qd: np.ndarray                #: joint speeds (rad/s)
    tau: np.ndarray               #: torques applied in the last step (N m)
    position_error: np.ndarray    #: q_ref - q of the last servo cycle (rad)


class ServoLoop:
    """Owns the arm model, the simulated cell and the joint servo; the motion layer calls `run` each motion cycle.

    References are given for the plant's current time. A single reference (1-D arrays) is continued
    inside the call with constant acceleration, q_ref + qd_ref t + qdd_ref t^2 / 2, exact for the
    piecewise constant-acceleration output of a time-optimal planner; 2-D arrays of shape
    (n_steps, n_joints) give one reference per servo step instead.
    """

    def __init__(self, arm: ArmModel | str = "irb2400", cell: SimCell | None = None,
                 gains: ServoGains = ServoGains()) -> None:
        self.arm = load_robot(arm) if isinstance(arm, str) else arm
        self.cell = cell if cell is not None else SimCell(self.arm.name)
        if self.cell.robot != self.arm.name:
            raise UsageError(f"the cell drives robot {self.cell.robot!r} but the arm model is {self.arm.name!r}")
        self.period_s: float = self.cell.timestep_s
        self._n = self.arm.n_joints
        # The servo gets its own model: the motion layer's calls on `arm` (another payload, say)
        # must never change the feed-forward in the middle of a motion.
        self.servo = JointServo(ArmModel(self.arm.spec), self.period_s, gains)
        self.on_step: list[Callable[[], None]] = []  #: called after every servo step (loggers, sensors)
        # The servo law runs in C inside the drives where the cell has them (the realistic plant);
        # the Python law (`JointServo.update`) is the reference and drives every other cell.
        self.drives = CompiledDrives(self.servo, self.cell) if getattr(self.cell, "drives", None) is not None else None
        self.compiled_law = self.drives is not None  #: False: the Python law, step by step
        self.drives_on = True  #: False: no torque, the brakes hold the joints (set_drives)
        self.twist: Any = None  #: the elastic gears' twist feed-forward (set_gear_twist), None: rigid gears
        self.observer: Any = None  #: the elastic gears' torque observer (set_gear_observer), None: none
        #: elastic gears' state feedback (set_state_feedback: a `servo.state_feedback.TwoMassStateFeedback`), None: the cascade
        self.state_feedback: Any = None
        #: the state feedback's steps compiled (servo/state_feedback_cycle.py), None: the Python loop below
        self._state_feedback_cycle: StateFeedbackCycle | None = None
        self._torque_sum_nm = np.zeros(self._n)   #: the motors' torque summed over the last call (the observer's input)
        self._kernels: Any = compiled.kernels("orc_rpl.servo.drive_kernels")   #: None where numba is not

    def set_gear_twist(self, twist: Any) -> None:
        """Lead each rotor by its gear's twist (a `servo.two_mass.GearTwist`; None: rigid gears). The
        references stay the links'; `state().q` is then the links' estimate (encoder minus the twist)."""
        self.twist = twist
        if self.drives is not None:
            self.drives.twist = twist

    def set_gear_observer(self, observer: Any) -> None:
        """Observe each gear's torque from the motor side after every call (a
        `servo.gear_observer.GearTorqueObserver`; None: none)."""
        self.observer = observer
        if self.drives is not None:
            self.drives.observed = observer is not None

    def set_state_feedback(self, law: Any) -> None:
        """Control elastic gears by state feedback (a `servo.state_feedback.TwoMassStateFeedback`, every step, the
        drives as torque motors; a motion cycle's steps as one compiled kernel where numba is) instead of the
        cascade; it also gives the twist `state().q` takes off.
        None: the cascade again (with rigid gears' references: set a twist again where there was one)."""
        if self.drives is not None:
            self.drives.release()
        if law is None and self.state_feedback is not None:
            self.compiled_law = False   # the cascade's Python law, as before the state feedback
        self.state_feedback = law
        self.twist = law
        self._state_feedback_cycle = None
        if law is not None and self.drives is not None and getattr(law, "_kernels", None) is not None:
            kernels = compiled.kernels("orc_rpl.servo.state_feedback_cycle_kernels")
            self._state_feedback_cycle = StateFeedbackCycle(self.servo, self.cell, law, kernels)
        if law is not None:
            # compiled: the steps of a motion cycle as one kernel (False, `use_compiled_law`: the Python loop)
            self.compiled_law = self._state_feedback_cycle is not None
            if self.drives is not None:
                self.drives.twist = None

    def set_drives(self, on: bool) -> None:
        """Switch the drives off (no torque, the brakes engaged) or on again (brakes released, the servo
        starts afresh from where the arm is: the caller's next references should start there)."""
        on = bool(on)
        if on == self.drives_on:
            return
        if self.drives is not None:
            self.drives.release()   # the cell's drives as plain torque motors
        self.servo.reset()
        self._no_torque = np.zeros(self.arm.n_joints)
        self.cell.set_brakes(not on)
        self.drives_on = on
        if on:   # braked, the rotors' momentum changed without the observer: it starts afresh at rest
            self._reset_observer()
            if self.state_feedback is not None:   # and the state feedback's filter, the links as the model's twist puts them
                zero = np.zeros(self._n)
                rest = np.array(self.servo.inverse_dynamics(self.cell.q, zero, zero))
                self.state_feedback.reset(self.cell.q - rest / self.state_feedback.stiffness_all, rest)

    def use_compiled_law(self, on: bool) -> None:
        """Run the servo law in the drives (C) or in Python, from the next step; a bumpless hand-over."""
        if on and self.drives is None:
            raise UsageError(f"the cell of {self.cell.robot!r} has no drives to run the servo law in")
        if not on and self.drives is not None:
            self.drives.release()
        self.compiled_law = on

    # -- the seam -------------------------------------------------------------

    def run(self, q_ref: Any, qd_ref: Any, qdd_ref: Any, n_steps: int = 4) -> ServoState:
        """Advance the plant by n_steps servo periods towards the reference; return the measured state."""
        q_ref, qd_ref, qdd_ref = self._checked_references(q_ref, qd_ref, qdd_ref, n_steps)
        callbacks = self.on_step
        if not self.drives_on:  # the references are ignored: the brakes hold the arm
            for _ in range(len(q_ref)):
                self.cell.step(self._no_torque)
                for callback in callbacks:
                    callback()
            return self.state()
        if self.state_feedback is not None:
            return self._run_state_feedback(q_ref, qd_ref, qdd_ref)
        if self.compiled_law:
            self.drives.run(q_ref, qd_ref, qdd_ref, self._each_step if callbacks else None)  # type: ignore[union-attr]
            if self.observer is not None:
                self._observe(self.cell.drives.mean_force, len(q_ref))
            return self.state()
        if self.twist is not None or self.observer is not None:
            return self._run_stepwise(q_ref, qd_ref, qdd_ref)
        update, step = self.servo.update, self.cell.step
        q, qd = self.cell.live_state()
        # The inner loop of the whole stack: 1,000 times per simulated second (measured: the step
        # itself costs about 3 us, so every numpy call and attribute lookup here shows).
        for q_r, qd_r, qdd_r in zip(q_ref, qd_ref, qdd_ref):
            if q is None:  # the cell cannot lend views of its state: take copies
                step(update(q_r, qd_r, qdd_r, self.cell.q, self.cell.qd))
            else:
                step(update(q_r, qd_r, qdd_r, q, qd))
            for callback in callbacks:
                callback()
        return self.state()

    def _run_stepwise(self, q_ref: np.ndarray, qd_ref: np.ndarray, qdd_ref: np.ndarray) -> ServoState:
        """The Python law on elastic gears, step by step: the motor-side references (two_mass.GearTwist) where
        the gears' twist is fed forward, and the motors' torques summed for the gear observer where there is one."""
        servo, cell = self.servo, self.cell
        q_m, qd_m = q_ref, qd_ref
        if self.twist is not None:
            rnea = servo.inverse_dynamics
            tau_ff = np.array([rnea(*row) for row in zip(q_ref, qd_ref, qdd_ref)])
            q_m, qd_m = self.twist.motor_references(q_ref, qd_ref, qdd_ref, tau_ff)
        torque_sum = self._torque_sum_nm
        torque_sum[:] = 0.0
        for i in range(len(q_m)):
            cell.step(servo.update(q_m[i], qd_m[i], qdd_ref[i], cell.q, cell.qd))
            torque_sum += cell.tau   # what the motors applied, after their saturation
            for callback in self.on_step:
                callback()
        if self.observer is not None:
            self._observe(torque_sum / len(q_m), len(q_m))
        return self.state()

    def _run_state_feedback(self, q_ref: np.ndarray, qd_ref: np.ndarray, qdd_ref: np.ndarray) -> ServoState:
        """Elastic gears under state feedback (servo/state_feedback.py), step by step, the drives as torque motors:
        the slow joints' torque from the state feedback, the others' from the cascade on the twisted references."""
        servo, cell, law = self.servo, self.cell, self.state_feedback
        rnea, sel = servo.inverse_dynamics, law.joints
        law.friction = servo.friction_in_use()
        cycle = self._state_feedback_cycle
        if self.compiled_law and cycle is not None and not self.on_step and cycle.fits():   # schedule and steps: one kernel
            rows = cycle.run(q_ref, qd_ref, qdd_ref)   # state()'s arrays, made by the kernel: rows of one new array
            return ServoState(cell.time_s, rows[0], rows[1], rows[2], rows[3])
        law.schedule(cell.q, qd_ref[0])
        for i in range(len(q_ref)):
            q, qd = np.array(cell.q), np.array(cell.qd)   # copies: the cell overwrites its measurements
            tau_ff = np.array(rnea(q_ref[i], qd_ref[i], qdd_ref[i]))
            theta_ref, theta_d_ref = law.references(q_ref[i], qd_ref[i], qdd_ref[i], tau_ff)
            tau = servo.update(theta_ref, theta_d_ref, qdd_ref[i], q, qd).copy()   # the cascade, every joint
            demand, ff = law.update(q_ref[i], qd_ref[i], theta_ref, theta_d_ref, tau_ff, q, qd)
            demand += servo.torque_offset[sel]
            tau[sel] = np.clip(demand, -law.tau_max, law.tau_max)
            servo.saturated[sel] = tau[sel] != demand
            servo.torque[sel] = tau[sel]
            cell.step(tau)
            law.applied(tau, qd)
            for callback in self.on_step:
                callback()
        servo.integral[sel] = law.unknown_torque_nm   # what the path velocity controller adds to the model's torque
        return self.state()

    def _observe(self, mean_torque_nm: np.ndarray, n_steps: int) -> None:
        """The gear observer after a call of n_steps steps with these mean motor torques."""
        self.observer.update(self.cell.q, self.cell.qd, mean_torque_nm, n_steps * self.period_s)

    def _each_step(self) -> None:
        for callback in self.on_step:
            callback()

    def _checked_references(self, q_ref: Any, qd_ref: Any, qdd_ref: Any, n_steps: int) -> tuple[np.ndarray, ...]:
        """The references of one call as (n_steps, n) arrays, checked once for the whole call."""
        q_ref, qd_ref, qdd_ref = np.asarray(q_ref, dtype=float), np.asarray(qd_ref, dtype=float), np.asarray(qdd_ref, dtype=float)
        shape = q_ref.shape
        if not (shape == qd_ref.shape == qdd_ref.shape and shape in ((n_steps, self._n), (self._n,))) or n_steps < 1:
            self._refuse(q_ref, qd_ref, qdd_ref, n_steps)
        kernels = self._kernels if compiled.ON else None
        if kernels is not None and len(shape) == 1:  # the compiled rows (servo/drive_kernels.py): the same numbers
            rows = (n_steps, self._n)
            q_steps, qd_steps, qdd_steps = np.empty(rows), np.empty(rows), np.empty(rows)
            if not kernels.reference_rows(q_ref, qd_ref, qdd_ref, self.period_s, q_steps, qd_steps, qdd_steps):
                raise UsageError("servo reference contains NaN or infinity")
            return q_steps, qd_steps, qdd_steps
        if len(shape) == 2 and kernels is not None:
            if not kernels.all_finite(q_ref, qd_ref, qdd_ref):
                raise UsageError("servo reference contains NaN or infinity")
            return q_ref, qd_ref, qdd_ref
        # count_nonzero: a plain C call, several times cheaper than np.all on these small arrays
        finite, size = np.isfinite, q_ref.size
        if (np.count_nonzero(finite(q_ref)) != size or np.count_nonzero(finite(qd_ref)) != size
                or np.count_nonzero(finite(qdd_ref)) != size):
            raise UsageError("servo reference contains NaN or infinity")
        if len(shape) == 2:
            return q_ref, qd_ref, qdd_ref
        n = self._n
        # Constant acceleration from the given state, the same expression step by step.
        t = (np.arange(n_steps) * self.period_s)[:, None]
        q_steps = q_ref + qd_ref * t + (0.5 * t * t) * qdd_ref
        qd_steps = qd_ref + qdd_ref * t
        q_steps[0], qd_steps[0] = q_ref, qd_ref
        return q_steps, qd_steps, np.broadcast_to(qdd_ref, (n_steps, n))

    def _refuse(self, q_ref: np.ndarray, qd_ref: np.ndarray, qdd_ref: np.ndarray, n_steps: int) -> None:
        """Raise the UsageError that says what is wrong with the shapes of a call."""
        n = self._n
        if n_steps < 1:
            raise UsageError(f"n_steps must be >= 1, got {n_steps}")
        if q_ref.ndim == 1:
            raise UsageError(f"references must each have {n} values, got {q_ref.shape}, {qd_ref.shape}, {qdd_ref.shape}")
        raise UsageError(f"per-step references must have shape ({n_steps}, {n})")

    def hold(self, q_ref: Any, n_steps: int) -> ServoState:
        """Servo to a fixed position at rest for n_steps (settling at the end of a FINE move)."""
        zero = np.zeros(self.arm.n_joints)
        return self.run(q_ref, zero, zero, n_steps)

    def state(self) -> ServoState:
        """The measured state now."""
        cell = self.cell
        q = cell.q if self.twist is None else cell.q - self.twist.twist_rad
        return ServoState(cell.time_s, q, cell.qd, cell.tau, self.servo.position_error.copy())

    # -- set-up ---------------------------------------------------------------

    def reset(self, q: Any = None) -> ServoState:
        """Plant and servo back to time 0 at rest at q (home if None)."""
        if self.drives is not None:
            self.drives.release()
        if self.twist is not None:
            # q is the links': the rotors rest ahead of them by the twist the model's weight torques give
            q_link, zero = np.array(self.arm.home_q if q is None else q, dtype=float), np.zeros(self._n)
            self.twist.hold(q_link, np.array(self.servo.inverse_dynamics(q_link, zero, zero)))
            q = q_link + self.twist.twist_rad
        self.cell.reset(q)
        self.servo.reset()
        self._reset_observer()
        return self.state()

    def _reset_observer(self) -> None:
        """At rest: the gears carry the torques the twist was set for (without a twist, the model's weight)."""
        if self.observer is None:
            return
        zero = np.zeros(self._n)
        self.observer.reset(self.twist.twist_rad / self.observer.compliance_rad_nm if self.twist is not None
                            else np.array(self.servo.inverse_dynamics(self.cell.q, zero, zero)))

    def set_payload(self, mass_kg: float, com_m: Any = (0.0, 0.0, 0.0), known: bool = True) -> None:
        """Put a payload on the flange; `known` also tells the feed-forward (False: the plant only, for identification)."""
        self.cell.set_payload(mass_kg, com_m)
        self.servo.arm.set_payload(mass_kg if known else 0.0, com_m if known else None)

    def set_torque_offset(self, tau_nm: Any) -> None:
        """Add a torque to the servo's reference from now on (force control, friction compensation); zeros to stop."""
        tau = np.asarray(tau_nm, dtype=float).reshape(-1)
        if tau.shape != (self.arm.n_joints,) or not np.all(np.isfinite(tau)):
            raise UsageError(f"torque offset must be {self.arm.n_joints} finite numbers (N m), got {tau_nm!r}")
        self.servo.torque_offset = tau

    def set_tuning(self, tuning: ServoTuning | None) -> None:
        """A task-specific tuning from the next step on (a motion WITH TUNING); None: the default gains again."""
        if self.drives is not None:
            self.drives.release()  # the tuning's bumpless switch works on the servo's integral
        law, q, zero = self.state_feedback, np.array(self.cell.q), np.zeros(self._n)
        weight = None if law is None else np.array(self.servo.inverse_dynamics(q, zero, zero))
        self.servo.set_tuning(tuning, q)
        if law is not None:  # the state feedback's integral action is its filter's unknown torques: bumpless there
            law.model_changed(np.array(self.servo.inverse_dynamics(q, zero, zero)) - weight)
            law.set_friction_smooth(None if tuning is None else tuning.friction_smooth_rad_s)

    def attach_logger(self, logger: Logger, every_steps: int = 1, tool: Any = None) -> None:
        """Record q, qd, tau, position_error, tau_ff and the TCP position ("tcp", m) every so many servo steps."""
        if every_steps < 1:
            raise UsageError(f"every_steps must be >= 1, got {every_steps}")
        servo, cell, arm = self.servo, self.cell, self.arm
        t_tool = None if tool is None else arm.transform(tool)
        logger.submit("q", lambda: cell.q)
        logger.submit("qd", lambda: cell.qd)
        logger.submit("tau", lambda: servo.torque)
        logger.submit("tau_ff", lambda: servo.torque_ff)
        logger.submit("position_error", lambda: servo.position_error)
        logger.submit("tcp", lambda: arm._fk(cell.q, t_tool)[:3, 3])
        counter = [0]

        def sample() -> None:
            if counter[0] % every_steps == 0:
                logger.update()
            counter[0] += 1

        self.on_step.append(sample)

    @property
    def time_s(self) -> float:
        """Plant time."""
        return self.cell.time_s
