"""The servo room's elastic-gear motion cycle compiled: `ServoLoop._run_state_feedback` as one numba kernel.

The Python loop (servo/loop.py) is the reference: per 1 ms step the model's torque of the link
reference (compiled RNEA), the state feedback's references, correction and torques for the slow joints
(the kernels of servo/state_feedback_kernels.py), the cascade of `JointServo.update` with its friction
feed-forward for every joint (the wrist's torques are its; the slow joints' are overwritten), the
limits, mj_step, the encoders' measurement and the copper sums, then the filter's prediction; no
return to Python between the steps. The drives stay torque motors: the law itself runs here, so the
wrist's cascade is the Python law's to the rounding (not the `pid` actuators' approximation of it).
Differences from the reference, all in the last bits: the RNEA and M_ii compiled, tanh from the C
library, and the plant's thermal model stepped at the call's end (as after the rigid gears' kernel).
"""

from __future__ import annotations

import numpy as np

from orc_rpl.plant.compiled import kernel, mj_step_intrinsic
from orc_rpl.plant.drive_kernels import measure
from orc_rpl.servo.rnea_kernel import mass_diagonal as mass_diagonal_at, rnea_row
from orc_rpl.servo.state_feedback_kernels import (compiled_law_views, law_predict, law_references, law_update,
                                                  schedule_on_views)

step = mj_step_intrinsic()

def scratch_size(n: int, m: int) -> int:
    """Floats in the work array `state_feedback_cycle` takes (`scratch`) for an arm of n joints, m of them slow."""
    return 23 * n + 2 * m + max(n, 7 * m)


#: Rows of the cascade's constants (`StateFeedbackCycle._law`): the kernel reads them by these indices.
KP, VELOCITY_BW, INTEGRAL_BW_DT, INTEGRAL_MAX, INTEGRAL_MIN, TAU_MAX = range(6)
LAW_ROWS = 6


@kernel
def state_feedback_cycle(model_address: int, data_address: int, q_ref: np.ndarray, qd_ref: np.ndarray,
                         qdd_ref: np.ndarray, noise: np.ndarray, schedule: bool, torque_offset: np.ndarray,
                         integral_before: np.ndarray, integral: np.ndarray, steps: int, friction: bool,
                         coulomb: np.ndarray, viscous: np.ndarray, snapshot: np.ndarray, law_buffer: np.ndarray,
                         moving: np.ndarray,
                         flags: np.ndarray, joints: np.ndarray, tuning: np.ndarray, body: np.ndarray,
                         gravity: np.ndarray, law: np.ndarray, inertia_every: int, smooth_inv: float, kv: np.ndarray,
                         ki_dt: np.ndarray, position_error: np.ndarray, velocity_error: np.ndarray, torque: np.ndarray,
                         saturated: np.ndarray, torque_ff: np.ndarray, velocity: np.ndarray, scratch: np.ndarray,
                         ctrl: np.ndarray,
                         force: np.ndarray, qpos: np.ndarray, qvel: np.ndarray, qpos_address: np.ndarray,
                         qvel_address: np.ndarray, count_per_rad: float, rad_per_count: float, q_meas: np.ndarray,
                         qd_meas: np.ndarray, tau_sq_sum: np.ndarray) -> None:  # pragma: no cover - compiled
    """`schedule` (the law's `schedule(q, qd_ref[0])`, q the measurement now), then len(q_ref) steps of
    `_run_state_feedback` after its schedule, the drives as torque motors.

    The state feedback is `law_buffer` (its arrays: servo/state_feedback_layout.py), `moving`, `flags`, `joints` and
    `tuning`; `law` the cascade's rows. `noise` has len(q_ref) + 1 rows (the speed noise the current measurement
    has, then each step's). The servo's signals end as the Python law leaves them: kv and ki_dt (scheduled every
    `inertia_every` steps counted from `steps`), the last step's position and velocity errors, torques,
    saturation flags, the cascade's feed-forward and the speeds it read; `integral` gets the cascade's
    integral with the slow joints' unknown torque (the filter's) in place of theirs. `snapshot` (4 x n) gets what
    `ServoLoop.state()` would copy after the call: the links' angles (the encoders' less the twist), the measured
    speeds, the applied torques and the position errors (one new array instead of four copies and a subtraction).
    """
    n_steps, n = q_ref.shape
    m = joints.shape[0]
    views = compiled_law_views(law_buffer, n, m)   # once, for the schedule and the steps
    if schedule:
        schedule_on_views(body, q_meas, qd_ref[0], joints, views, moving, flags, tuning)
    (twist_rad, rotor_all, stiffness_all, held_link, held_rotor, link_other, _, _, _, law_tau_max, state, link_inertia,
     k, l, ad, bd, _, _, _, _, _, _, _, _) = views
    # the steps' work arrays: slices of `scratch` (scratch_size floats: a dozen small allocations a call saved)
    q, qd, tau_link, theta_ref, theta_d_ref = (scratch[0:n], scratch[n : 2 * n], scratch[2 * n : 3 * n],
                                               scratch[3 * n : 4 * n], scratch[4 * n : 5 * n])
    last, mass, tau = scratch[5 * n : 6 * n], scratch[6 * n : 7 * n], scratch[7 * n : 8 * n]
    demand, ff = scratch[8 * n : 8 * n + m], scratch[8 * n + m : 8 * n + 2 * m]
    at = 8 * n + 2 * m
    work, law_work = scratch[at : at + 15 * n].reshape((n, 15)), scratch[at + 15 * n : at + 15 * n + max(n, 7 * m)]
    for j in range(n):
        last[j] = integral_before[j]
    for i in range(n_steps):
        for j in range(n):   # copies: the measurement is overwritten after the step
            q[j], qd[j] = q_meas[j], qd_meas[j]
        rnea_row(body, gravity, q_ref[i], qd_ref[i], qdd_ref[i], tau_link, work)
        law_references(q_ref[i], qd_ref[i], qdd_ref[i], tau_link, joints, rotor_all, stiffness_all, state, moving,
                       held_link, link_inertia, tuning, twist_rad, link_other, theta_ref, theta_d_ref, law_work)
        # JointServo.update (with _update_tuned's friction) on the rotors' references, every joint
        if steps % inertia_every == 0:
            mass_diagonal_at(body, q, mass)
            for j in range(n):
                kv[j] = mass[j] * law[VELOCITY_BW, j]
                ki_dt[j] = kv[j] * law[INTEGRAL_BW_DT, j]
        steps += 1
        rnea_row(body, gravity, theta_ref, theta_d_ref, qdd_ref[i], torque_ff, work)
        for j in range(n):
            extra = 0.0
            if friction:
                speed = ((theta_ref[j] - q[j]) * law[KP, j] + theta_d_ref[j]) * smooth_inv
                extra = extra + np.tanh(speed) * coulomb[j]
                extra = extra + theta_d_ref[j] * viscous[j]
            extra = extra + torque_offset[j]
            error = theta_ref[j] - q[j]
            speed_error = (theta_d_ref[j] - qd[j]) + error * law[KP, j]
            position_error[j], velocity_error[j] = error, speed_error
            value = min(last[j] + ki_dt[j] * speed_error, law[INTEGRAL_MAX, j])
            value = max(value, law[INTEGRAL_MIN, j])
            total = ((kv[j] * speed_error + torque_ff[j]) + value) + extra
            t = max(min(total, law[TAU_MAX, j]), -law[TAU_MAX, j])
            saturated[j] = t != total
            integral[j] = last[j] if saturated[j] else value   # the anti-windup
            tau[j] = t
        # the slow joints: the state feedback's torques in place of the cascade's
        law_update(q_ref[i], qd_ref[i], theta_ref, theta_d_ref, tau_link, q, qd, joints, state, l, k, moving,
                   held_link, held_rotor, friction, coulomb, viscous, tuning, demand, ff, law_work)
        for c in range(m):
            j = joints[c]
            wanted = demand[c] + torque_offset[j]
            t = min(max(wanted, -law_tau_max[c]), law_tau_max[c])
            saturated[j] = t != wanted
            tau[j] = t
        for j in range(n):
            torque[j] = tau[j]
            ctrl[3 * j + 2] = tau[j]
            last[j] = integral[j]
        step(model_address, data_address)
        for j in range(n):
            f = force[j]
            tau_sq_sum[j] = tau_sq_sum[j] + f * f
        measure(qpos, qvel, qpos_address, qvel_address, noise[i + 1], count_per_rad, rad_per_count, q_meas, qd_meas)
        law_predict(tau, qd, joints, state, ad, bd, moving, held_rotor, link_other, friction, coulomb, viscous, tuning,
                    law_work)
    for j in range(n):
        velocity[j] = qd[j]
        snapshot[0, j] = q_meas[j] - twist_rad[j]
        snapshot[1, j] = qd_meas[j]
        snapshot[2, j] = force[j]
        snapshot[3, j] = position_error[j]
    for c in range(m):   # what the path velocity controller adds to the model's torque: the filter's unknown torque
        w = state[4 * m + c]
        integral[joints[c]] = -((w if moving[c] else held_link[c]) + (held_rotor[c] if moving[c] else w))
