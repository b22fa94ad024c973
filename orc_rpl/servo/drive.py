"""The servo room's drives in C: the servo law of `JointServo` run as MuJoCo PID actuators, one motion cycle per call."""

from __future__ import annotations

from typing import Any

import numpy as np

from orc_rpl.plant import compiled
from orc_rpl.servo.control import FRICTION_SMOOTH_RAD_S, JointServo

add, subtract, multiply, tanh, minimum, maximum, copyto = (np.add, np.subtract, np.multiply, np.tanh, np.minimum, np.maximum,
                                                       np.copyto)


class CompiledDrives:
    """Runs `JointServo`'s law inside mj_step, with the gains and feed-forward computed once a motion cycle.

    The law tau = kv (qd_ref - qd + kp (q_ref - q)) + I + tau_ff, I = integral of kv ki (the same
    velocity error), is a PID on the position error: tau = kv (kp + ki) e + kv (qd_ref - qd)
    + kv ki kp * integral(e) + tau_ff, with e = q_ref - q. The drives (plant/realistic.py) compute that
    in C each step; this class schedules kv = M_ii(q) * bandwidth at the measured pose at the start of
    each call (the Python law: every `inertia_every_steps` = one motion cycle) and gives them, one
    row a step, the references and the feed-forward: the model's inverse dynamics of the reference,
    the nominal friction, a tuning's terms, the torque offset, and the speed noise the servo reads
    (-kv * noise: the drive's velocity input is the plant's own speed).

    Differences from the Python law, all small (tests/servo/test_drives.py bounds their effect):
    the encoder's quantisation (half a count) is not seen inside the cycle; the friction
    feed-forward's position correction is the one at the start of the cycle; the integral is not
    frozen while a motor saturates (its limit, 0.25 tau_max, still holds).
    """

    def __init__(self, servo: JointServo, cell: Any) -> None:
        self.servo, self.cell = servo, cell
        n = servo.arm.n_joints
        self._ff = np.zeros((0, n))
        self._friction_of: Any = None   #: the friction the rows below were filled for (`_friction_rows`)
        self._work, self._integral = np.zeros(n), np.zeros(n)
        self._gains = np.zeros((3, n))
        self._gain_p, self._gain_i, self._kv_ibw = self._gains   # views of its rows
        self._kp, self._kv, self._ibw = np.zeros(n), np.zeros(n), np.zeros(n)
        self._pid_p, self._pid_i = np.zeros(n), np.zeros(n)   #: kp + ki and ki * kp of the law, per kv
        self._integral_start, self._q_before, self._qd_before = np.zeros(n), np.zeros(n), np.zeros(n)
        self._integral_a, self._integral_b = np.zeros(n), np.zeros(n)   #: servo.integral's two arrays (run)
        self._rnea_rows = servo.arm.inverse_dynamics_rows_function()
        self._tau_abs = np.zeros(n)
        self.engaged = False   #: the drives hold the servo's integral (False: the Python law has it)
        self._law_of: Any = None   #: the (kp, friction) the law's constants below were made for
        self._kernels: Any = compiled.kernels("orc_rpl.servo.drive_kernels")   #: None where numba is not
        if self._kernels is not None:
            self._law, self._scratch = np.zeros((self._kernels.LAW_ROWS, n)), np.zeros((self._kernels.SCRATCH_ROWS, n))
        #: the kernel's feed-forward and M_ii compiled (servo/rnea_kernel.py; False: Pinocchio's, the reference)
        self.compiled_rnea = True
        self._no_body = np.zeros((0, 29))
        self._body = self._no_body   #: the model's rows for the compiled RNEA (its own: a new array when the payload changes)
        self._gravity = servo.arm.gravity_m_s2
        self._mass_diagonal = np.zeros(n)
        self._tail: Any = None   #: the kernel's arguments that change only with the ones checked in _run_kernel
        self.twist: Any = None  #: elastic gears' twist feed-forward (servo.two_mass.GearTwist), None: rigid gears
        #: a gear observer reads the drives' mean torque of each call (`PidDrives.drive`'s; the kernel has none)
        self.observed = False

    def engage(self) -> None:
        """Take over from the Python law: the drives' integral from the servo's (bumpless)."""
        self.engaged = True
        q, _ = self.cell.live_state()
        self._schedule(q)

    def release(self) -> None:
        """Hand back to the Python law: the servo's integral from the drives', the drives as torque motors."""
        if self.engaged:
            self.servo.integral = self.cell.drives.integral_nm() + self._kv * self._ibw * self.servo.position_error
            self.cell.drives.torque_mode()
            self.servo._steps = 0  # its gains are scheduled again at the next step
            self.engaged = False

    def _constants(self) -> None:
        """The law's constants, made again after another tuning (or at the first call)."""
        servo = self.servo
        if servo._kp is not self._kp:
            self._kp, self._ibw = servo._kp, servo._integral_bw_dt / servo.period_s
            self._pid_p, self._pid_i = self._kp + self._ibw, self._ibw * self._kp
            self._per_kv = np.stack([self._pid_p, self._pid_i, self._ibw])   #: one ufunc gives the three gains
            self._friction_p = self._kp * (1.0 / FRICTION_SMOOTH_RAD_S)
            self._integral_max = servo._integral_max

    def _schedule(self, q: np.ndarray) -> None:
        """Gains at the measured pose (the Python law's gain scheduling), written into the drives."""
        servo = self.servo
        self._constants()
        kv, pid_p, pid_i = self._kv, self._gain_p, self._gain_i
        multiply(servo.arm.mass_matrix_diagonal_unchecked(q), servo._velocity_bw, kv)
        multiply(kv, self._per_kv, self._gains)  # rows: kv (kp + ki), kv ki kp, kv ki
        # The integral torque of the Python law is kept across the new kv, not the PID's ki * int(e):
        # its kv ki e part changes with kv (unchecked, it drifts by about 10 N m over a fast move)
        work = self._work
        multiply(self._kv_ibw, servo.position_error, work)
        subtract(servo.integral, work, work)
        self.cell.drives.set_drive_gains(pid_p, kv, pid_i, self._integral_max, work)

    def run(self, q_ref: np.ndarray, qd_ref: np.ndarray, qdd_ref: np.ndarray, each_step: Any = None) -> None:
        """One call of the servo loop: len(q_ref) steps of per-step references (rows), the drives in C."""
        servo, cell = self.servo, self.cell
        if not self.engaged:
            self.engage()
        if (compiled.ON and self._kernels is not None and each_step is None and self.twist is None
                and not self.observed and servo.tuning is None and cell.drives.kernel_fits()):
            self._run_kernel(q_ref, qd_ref, qdd_ref)
            return
        q, _ = cell.live_state()
        self._schedule(q)
        n_steps = len(q_ref)
        self._rows_ready(n_steps)
        # per-joint values are spread over the rows once (copyto) before they meet a (rows, joints) array:
        # numpy 2.4 broadcasts a row three times slower than it copies it; the numbers are the same
        ff, work, rnea, spread = self._ff, self._rows, self._rnea, self._spread
        self._rnea_rows(q_ref, qd_ref, qdd_ref, rnea)  # the model's rigid-body torques, one C call for the rows
        servo.torque_ff = rnea[-1]  # a view: the servo's signals are overwritten each cycle
        ff_so_far = rnea   # the feed-forward is summed into ff from here (the same sums in the same order)
        if self.twist is not None:  # elastic gears: the rotor leads the link by the twist (two_mass.py)
            q_ref, qd_ref = self.twist.motor_references(q_ref, qd_ref, qdd_ref, rnea)
        if servo._coulomb is not None:
            # the speed the loop asks for, with the position error at the start of the cycle (/ smoothing)
            error = self._work
            subtract(q_ref[0], q, error)
            multiply(error, self._friction_p, error)
            copyto(spread, error)
            multiply(qd_ref, self._smooth_rows, work)
            add(work, spread, work)
            tanh(work, work)
            multiply(work, self._coulomb_rows, work)
            add(rnea, work, ff)
            multiply(qd_ref, self._viscous_rows, work)
            add(ff, work, ff)
            ff_so_far = ff
        if servo.tuning is not None:
            if ff_so_far is rnea:
                ff[:] = rnea
            ff += servo._d_inertia * qdd_ref + servo._d_viscous * qd_ref + servo._d_offset
            ff_so_far = ff
        copyto(spread, servo.torque_offset)
        add(ff_so_far, spread, ff)
        noise = cell.noise_rows(n_steps)
        copyto(spread, self._kv)
        multiply(noise, spread, work)
        subtract(ff, work, ff)   # the velocity loop reads the noisy speed
        state = cell.drives.integral_state
        true_q, true_qd = cell.true_live_state()
        start, q_before, qd_before = self._integral_start, self._q_before, self._qd_before
        start[:] = state
        integral_before = servo.integral  # not written: the new integral goes into another array
        q_before[:] = true_q
        qd_before[:] = true_qd
        if each_step is None:
            cell.drives.drive(q_ref, qd_ref, ff)
            self._signals(q_ref[-1], qd_ref[-1], False)
        else:
            row = [0]

            def step() -> None:
                self._signals(q_ref[row[0]], qd_ref[row[0]])
                row[0] += 1
                each_step()

            cell.drives.drive(q_ref, qd_ref, ff, step)
        servo._steps += n_steps
        # The Python law's integral over the call, from the drives' states: it sums h (qd_ref - qd + kp e)
        # step by step, and with MuJoCo's semi-implicit Euler sum(h qd_k) = q_n - q_0 - h (qd_n - qd_0)
        # and sum(h e_k) is the drives' integral state's change (the noise the law reads is known)
        true_q, true_qd = cell.true_live_state()
        subtract(qd_ref, noise, work)
        increment = add.reduce(work, 0)
        subtract(true_qd, qd_before, qd_before)
        add(increment, qd_before, increment)
        multiply(increment, servo.period_s, increment)
        subtract(true_q, q_before, q_before)
        subtract(increment, q_before, increment)
        subtract(state, start, q_before)
        multiply(q_before, self._kp, q_before)
        add(increment, q_before, increment)
        multiply(increment, self._kv_ibw, increment)
        if True in servo.saturated.tolist():
            # the anti-windup, once a call: a motor that ended it saturated keeps its integral
            increment[servo.saturated] = 0.0
        # into one of two arrays, never the one before: servo.integral alternates as the Python law's does
        integral = self._integral_a if integral_before is not self._integral_a else self._integral_b
        add(integral_before, increment, integral)
        minimum(integral, servo._integral_max, out=integral)
        maximum(integral, servo._integral_min, out=integral)
        servo.integral = integral

    def _run_kernel(self, q_ref: np.ndarray, qd_ref: np.ndarray, qdd_ref: np.ndarray) -> None:
        """`run` as one compiled kernel (rigid gears, no tuning, no per-step callbacks): the same numbers."""
        servo, cell = self.servo, self.cell
        self._constants()
        n_steps = len(q_ref)
        self._rows_ready(n_steps)
        if self._law_of is None or self._law_of[0] is not servo._kp or self._law_of[1] is not servo._coulomb:
            self._law_rows()
        rnea, mass_diagonal = self._rnea, self._mass_diagonal
        body = servo.arm.rigid_body_rows() if self.compiled_rnea else None
        if body is None:
            body = self._no_body
        if body is not self._body:   # the model makes its rows again when the payload changes
            self._body, self._tail = body, None
        if self._body is self._no_body:   # Pinocchio's M_ii and rigid-body torques (one C call for the rows)
            q, _ = cell.live_state()
            mass_diagonal = servo.arm.mass_matrix_diagonal_unchecked(q)
            self._rnea_rows(q_ref, qd_ref, qdd_ref, rnea)
        if qdd_ref.strides[0] == 0:   # one acceleration broadcast over the rows: the kernel reads rows
            qdd_ref = np.ascontiguousarray(qdd_ref)
        servo.torque_ff = rnea[-1]
        noise = cell.noise_rows(n_steps + 1)   # the steps' rows and the measurement's after them
        integral_before = servo.integral
        integral = self._integral_a if integral_before is not self._integral_a else self._integral_b
        tail = self._tail
        if tail is None or tail[3] is not mass_diagonal:   # made again after a change above (or Pinocchio's M_ii)
            tail = self._tail = (self._body, self._gravity, rnea, mass_diagonal, self._law, servo._coulomb is not None,
                                 1.0 / FRICTION_SMOOTH_RAD_S, servo.period_s, servo.position_error, servo.torque,
                                 servo.saturated, self._kv, self._gains, self._ff, self._scratch,
                                 *cell.drives.kernel_arrays())
        cell.drives.run_kernel(self._kernels.drive_cycle, (q_ref, qd_ref, qdd_ref, noise, servo.torque_offset,
                                                           integral_before, integral), tail)
        servo._steps += n_steps
        servo.integral = integral

    def _law_rows(self) -> None:
        """The law's constants as the rows the kernel reads (servo/drive_kernels.py)."""
        servo, law, k = self.servo, self._law, self._kernels
        law[k.VELOCITY_BW], law[k.PID_P], law[k.PID_I], law[k.INTEGRAL_BW] = (servo._velocity_bw, self._pid_p,
                                                                             self._pid_i, self._ibw)
        law[k.KP], law[k.FRICTION_P] = self._kp, self._friction_p
        law[k.COULOMB], law[k.VISCOUS] = ((0.0, 0.0) if servo._coulomb is None else (servo._coulomb, servo._viscous))
        law[k.INTEGRAL_MAX], law[k.INTEGRAL_MIN], law[k.TAU_MAX] = servo._integral_max, servo._integral_min, servo._tau_max
        self._law_of, self._tail = (servo._kp, servo._coulomb), None

    def _rows_ready(self, n_steps: int) -> None:
        """The work arrays fit a call of n_steps rows and hold the friction now (made again only on a change)."""
        if self._ff.shape[0] != n_steps:
            self._rows_for(n_steps)
        elif self._friction_of is not self.servo._coulomb:
            self._friction_rows()

    def _rows_for(self, n_steps: int) -> None:
        """Work arrays of a call of n_steps rows, and the friction's constants spread over them."""
        shape = (n_steps, self.servo.arm.n_joints)
        self._ff, self._rows, self._rnea, self._spread = np.zeros(shape), np.zeros(shape), np.zeros(shape), np.zeros(shape)
        self._smooth_rows = np.full(shape, 1.0 / FRICTION_SMOOTH_RAD_S)
        self._coulomb_rows, self._viscous_rows = np.zeros(shape), np.zeros(shape)
        self._tail = None
        self._friction_rows()

    def _friction_rows(self) -> None:
        """The friction's constants spread over the rows, in place (the gearboxes' estimate changes it every 0.1 s;
        nothing else of the rows depends on it)."""
        servo = self.servo
        self._friction_of = servo._coulomb
        if servo._coulomb is not None:
            self._coulomb_rows[:], self._viscous_rows[:] = servo._coulomb, servo._viscous

    def _integral_now(self) -> None:
        """servo.integral: the Python law's integral torque I = kv ki e + ki_pid * integral(e)."""
        servo, work, integral = self.servo, self._work, self._integral
        multiply(self._kv_ibw, servo.position_error, work)
        multiply(self.cell.drives.integral_state, self.cell.drives.ki, integral)
        add(integral, work, integral)
        servo.integral = integral

    def _signals(self, q_ref: np.ndarray, qd_ref: np.ndarray, integral: bool = True) -> None:
        """The servo's internal signals after a step, as the Python law shows them (measured state).

        position_error, integral (unless False: the end of a call sets it), torque and saturated;
        velocity_error is the Python law's only.
        """
        servo, cell = self.servo, self.cell
        q, _ = cell.live_state()
        error = servo.position_error
        # the Python law's error is the last step's, measured before it: the reference a step on, against now
        multiply(qd_ref, servo.period_s, error)
        add(error, q_ref, error)
        subtract(error, q, error)
        if integral:
            self._integral_now()
        tau = servo.torque
        tau[:] = cell.drives.force
        np.abs(tau, self._tau_abs)
        np.greater_equal(self._tau_abs, servo._tau_max, servo.saturated)
