"""The servo room's elastic-gear motion cycle compiled: the fused kernel's arguments, kept between calls."""

from __future__ import annotations

from typing import Any

import numpy as np

from orc_rpl.plant import compiled
from orc_rpl.servo.control import FRICTION_SMOOTH_RAD_S, JointServo


class StateFeedbackCycle:
    """Runs `ServoLoop._run_state_feedback`'s steps as one kernel (servo/state_feedback_cycle_kernels.py).

    Made by the loop when the cell has drives and numba is there; `fits` says whether a call may take
    the kernel (no tuning, nothing to run between the steps, a model the compiled RNEA can read);
    `run` then does what the Python loop does (its schedule, then its steps), to the rounding.
    """

    def __init__(self, servo: JointServo, cell: Any, law: Any, kernels: Any) -> None:
        self.servo, self.cell, self.law, self._kernels = servo, cell, law, kernels
        n = servo.arm.n_joints
        self._law = np.zeros((kernels.LAW_ROWS, n))
        #: the (kp, velocity_bw) arrays the rows were made from (a tuning sets them with integral_bw_dt, all new arrays)
        self._law_of: Any = None
        self._body: Any = None   #: the model's rows for the compiled RNEA (its own: a new array when the payload changes)
        self._gravity = servo.arm.gravity_m_s2
        self._torque_ff, self._velocity, self._no_friction = np.zeros(n), np.zeros(n), np.zeros(n)
        self._scratch = np.zeros(kernels.scratch_size(n, len(law.joints)))   #: the kernel's work arrays
        self._tail: Any = None

    def fits(self) -> bool:
        """True when this call can be the kernel: no task tuning, no per-step work, a revolute chain."""
        servo = self.servo
        if (servo.tuning is not None or not compiled.ON or self.law._kernels is None
                or not self.cell.drives.kernel_fits()):
            return False
        body = servo.arm.rigid_body_rows()
        if body is not self._body:   # the model makes its rows again when the payload changes
            self._body, self._tail = body, None
        return body is not None

    def run(self, q_ref: np.ndarray, qd_ref: np.ndarray, qdd_ref: np.ndarray) -> np.ndarray:
        """The call's schedule (the law's, `schedule(cell.q, qd_ref[0])`) and steps, the drives as torque motors;
        returns the state after them as rows (a new array): the links' angles, the measured speeds, the applied
        torques, the position errors (`ServoLoop.state()`'s q, qd, tau and position_error)."""
        servo, law = self.servo, self.law
        if self._law_of is None or self._law_of[0] is not servo._kp or self._law_of[1] is not servo._velocity_bw:
            self._law_rows()
        schedule = law.solved   # else (after a reset) solved in Python first: numba has no DARE solver
        if not schedule:
            law.schedule(self.cell.q, qd_ref[0])
        if qdd_ref.strides[0] == 0:   # one acceleration broadcast over the rows: the kernel reads rows
            qdd_ref = np.ascontiguousarray(qdd_ref)
        n_steps = len(q_ref)
        noise = self.cell.noise_rows(n_steps + 1)   # the current measurement's row, then the steps'
        friction = servo.friction_in_use()
        coulomb, viscous = friction if friction is not None else (self._no_friction, self._no_friction)
        integral_before, integral = servo.integral, servo._integral_next
        tail = self._tail
        if tail is None:
            tail = self._tail = (law._buffer, law.moving, law._flags, law.joints, law._tuning, self._body, self._gravity,
                                 self._law, servo._inertia_every, 1.0 / FRICTION_SMOOTH_RAD_S, servo._kv, servo._ki_dt,
                                 servo.position_error, servo.velocity_error, servo.torque, servo.saturated,
                                 self._torque_ff, self._velocity, self._scratch,
                                 *self.cell.drives.torque_kernel_arrays())
        snapshot = np.empty((4, len(self._velocity)))
        self.cell.drives.run_kernel(self._kernels.state_feedback_cycle, (
            q_ref, qd_ref, qdd_ref, noise, schedule, servo.torque_offset, integral_before, integral, servo._steps,
            friction is not None, coulomb, viscous, snapshot), tail)
        servo._steps += n_steps
        servo.integral, servo._integral_next = integral, integral_before
        servo.torque_ff, servo.velocity = self._torque_ff, self._velocity
        return snapshot

    def _law_rows(self) -> None:
        """The cascade's constants as the rows the kernel reads."""
        servo, law, k = self.servo, self._law, self._kernels
        law[k.KP], law[k.VELOCITY_BW], law[k.INTEGRAL_BW_DT] = servo._kp, servo._velocity_bw, servo._integral_bw_dt
        law[k.INTEGRAL_MAX], law[k.INTEGRAL_MIN] = servo._integral_max, servo._integral_min
        law[k.TAU_MAX] = servo._tau_max
        self._law_of, self._tail = (servo._kp, servo._velocity_bw), None
