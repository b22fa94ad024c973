"""The servo room's motion cycle on the drives, compiled: `CompiledDrives.run`'s numpy work fused into one kernel.

The numpy code in servo/drive.py is the reference: the kernel does the same operations in the same
order on the same numbers (tests/servo/test_drive_kernels.py compares the two on recorded runs).
"""

from __future__ import annotations

import numpy as np

from orc_rpl.plant.compiled import kernel
from orc_rpl.plant.drive_kernels import drive_rows, measure
from orc_rpl.servo.rnea_kernel import mass_diagonal as mass_diagonal_at, rnea_row

#: Rows of the law's constants (`CompiledDrives._law`): the kernel reads them by these indices.
VELOCITY_BW, PID_P, PID_I, INTEGRAL_BW, KP, FRICTION_P, COULOMB, VISCOUS, INTEGRAL_MAX, INTEGRAL_MIN, TAU_MAX = range(11)
LAW_ROWS = 11
#: Rows of the scratch array: the start of the call's integral state, q and qd, the increment, squares.
STATE_START, Q_BEFORE, QD_BEFORE, INCREMENT, SQUARES = range(5)
SCRATCH_ROWS = 5


@kernel
def drive_cycle(model_address: int, data_address: int, q_ref: np.ndarray, qd_ref: np.ndarray, qdd_ref: np.ndarray,
                noise: np.ndarray, torque_offset: np.ndarray, integral_before: np.ndarray, integral: np.ndarray,
                body: np.ndarray, gravity: np.ndarray, rnea: np.ndarray, mass_diagonal: np.ndarray, law: np.ndarray,
                friction: bool, smooth: float, period_s: float, position_error: np.ndarray, torque: np.ndarray,
                saturated: np.ndarray, kv: np.ndarray, gains: np.ndarray, ff: np.ndarray, scratch: np.ndarray,
                ctrl: np.ndarray, act: np.ndarray, force: np.ndarray,
                gainprm: np.ndarray, biasprm: np.ndarray, dynprm: np.ndarray, qpos: np.ndarray, qvel: np.ndarray,
                qpos_address: np.ndarray, qvel_address: np.ndarray, count_per_rad: float, rad_per_count: float,
                q_meas: np.ndarray, qd_meas: np.ndarray, tau_sq_sum: np.ndarray) -> None:  # pragma: no cover - compiled
    """One motion cycle of `CompiledDrives.run` (rigid gears, no tuning, no per-step callbacks).

    Gains at the measured pose (q_meas, mass_diagonal = the model's M_ii there) written into the
    drives, the feed-forward rows, len(q_ref) steps of mj_step, the copper losses, the measurement,
    the servo's signals and the Python law's integral carried over (into `integral`, clipped).
    `noise` has len(q_ref) + 1 rows: the speed noise of the steps and of the measurement after them.
    The feed-forward's rigid-body torques and M_ii: compiled (servo/rnea_kernel.py) from the model's
    rows `body` into `rnea` and `mass_diagonal` when `body` has rows, else as given (Pinocchio's).
    """
    n_steps, n = q_ref.shape
    if body.shape[0] == n:
        mass_diagonal_at(body, q_meas, mass_diagonal)   # the gains' M_ii at the measured pose
        rnea_work = np.empty((n, 15))
        for i in range(n_steps):
            rnea_row(body, gravity, q_ref[i], qd_ref[i], qdd_ref[i], rnea[i], rnea_work)
    start, q_before, qd_before = scratch[STATE_START], scratch[Q_BEFORE], scratch[QD_BEFORE]
    increment = scratch[INCREMENT]
    for j in range(n):
        # _schedule: kv at the measured pose, the PID's gains, the integral torque kept across the new kv
        k = mass_diagonal[j] * law[VELOCITY_BW, j]
        kv[j] = k
        gain_p, gain_i, kv_ibw = k * law[PID_P, j], k * law[PID_I, j], k * law[INTEGRAL_BW, j]
        gains[0, j], gains[1, j], gains[2, j] = gain_p, gain_i, kv_ibw
        kept = integral_before[j] - kv_ibw * position_error[j]
        # PidDrives.set_drive_gains
        gainprm[j, 0] = gain_i
        biasprm[j, 1] = -gain_p
        biasprm[j, 2] = -k
        if gain_i > 0.0:
            act[j] = kept / gain_i
            dynprm[j, 0] = law[INTEGRAL_MAX, j] / gain_i
        else:
            act[j] = 0.0
            dynprm[j, 0] = 0.0
        error = (q_ref[0, j] - q_meas[j]) * law[FRICTION_P, j]
        for i in range(n_steps):
            total = rnea[i, j]
            if friction:
                # the speed the loop asks for, with the position error at the start of the cycle (/ smoothing)
                total = total + np.tanh(qd_ref[i, j] * smooth + error) * law[COULOMB, j]
                total = total + qd_ref[i, j] * law[VISCOUS, j]
            total = total + torque_offset[j]
            ff[i, j] = total - noise[i, j] * k   # the velocity loop reads the noisy speed
        start[j] = act[j]
        q_before[j] = qpos[qpos_address[j]]
        qd_before[j] = qvel[qvel_address[j]]
    drive_rows(model_address, data_address, q_ref, qd_ref, ff, ctrl, force, scratch[SQUARES], tau_sq_sum)
    measure(qpos, qvel, qpos_address, qvel_address, noise[n_steps], count_per_rad, rad_per_count, q_meas, qd_meas)
    last = n_steps - 1
    for j in range(n):
        # _signals: the last step's error, measured before it; the torque and its saturation
        position_error[j] = (qd_ref[last, j] * period_s + q_ref[last, j]) - q_meas[j]
        tau = force[j]
        torque[j] = tau
        saturated[j] = abs(tau) >= law[TAU_MAX, j]
        # the Python law's integral over the call from the drives' states (drive.py: the same sums)
        s = qd_ref[0, j] - noise[0, j]
        for i in range(1, n_steps):
            s = s + (qd_ref[i, j] - noise[i, j])
        s = s + (qvel[qvel_address[j]] - qd_before[j])
        s = s * period_s
        s = s - (qpos[qpos_address[j]] - q_before[j])
        s = s + (act[j] - start[j]) * law[KP, j]
        s = s * gains[2, j]
        increment[j] = s
    for j in range(n):
        # the anti-windup, once a call: a motor that ended it saturated keeps its integral
        value = integral_before[j] + (0.0 if saturated[j] else increment[j])
        value = min(value, law[INTEGRAL_MAX, j])
        integral[j] = max(value, law[INTEGRAL_MIN, j])


@kernel
def reference_rows(q_ref: np.ndarray, qd_ref: np.ndarray, qdd_ref: np.ndarray, period_s: float, q_rows: np.ndarray,
                   qd_rows: np.ndarray, qdd_rows: np.ndarray) -> bool:  # pragma: no cover - compiled
    """`ServoLoop._checked_references` of one reference: False if a value is not finite, else the rows of
    constant acceleration q + qd t + (t t / 2) qdd, qd + qdd t (t = i period) written, the same expressions."""
    n = q_ref.shape[0]
    for j in range(n):
        if not (np.isfinite(q_ref[j]) and np.isfinite(qd_ref[j]) and np.isfinite(qdd_ref[j])):
            return False
    for i in range(q_rows.shape[0]):
        t = i * period_s
        half_t_t = 0.5 * t * t
        for j in range(n):
            if i == 0:
                q_rows[i, j], qd_rows[i, j] = q_ref[j], qd_ref[j]
            else:
                q_rows[i, j] = q_ref[j] + qd_ref[j] * t + half_t_t * qdd_ref[j]
                qd_rows[i, j] = qd_ref[j] + qdd_ref[j] * t
            qdd_rows[i, j] = qdd_ref[j]
    return True


@kernel
def all_finite(q_ref: np.ndarray, qd_ref: np.ndarray, qdd_ref: np.ndarray) -> bool:  # pragma: no cover - compiled
    """True when every value of the three (rows, joints) arrays of one shape is finite (any memory layout)."""
    for i in range(q_ref.shape[0]):
        for j in range(q_ref.shape[1]):
            if not (np.isfinite(q_ref[i, j]) and np.isfinite(qd_ref[i, j]) and np.isfinite(qdd_ref[i, j])):
                return False
    return True
