"""The servo room's state feedback compiled: a motion cycle's model and gains (`TwoMassStateFeedback.schedule`) in numba.

The numpy code in servo/state_feedback.py is the reference: the kernel builds the same sampled
model, the same weights and noises, and runs the same Riccati iterations, expression for expression
(tests/servo/test_state_feedback_kernels.py compares the two on a recorded run, to 1e-10). Profiled on
bench_motion's program (elastic, state feedback): the schedule was about half of the servo's time, a
hundred small numpy calls a motion cycle on matrices of 15 x 15 at most.
"""

from __future__ import annotations

import numpy as np

from orc_rpl.plant.compiled import kernel

#: Entries of the `tuning` array (`TwoMassStateFeedback._tuning`): the kernel reads the design's constants by these.
BANDWIDTH, MOTOR_WEIGHT, ROTOR_NOISE, LINK_NOISE, WALK, REST_WALK, ANGLE_NOISE, SPEED_NOISE, PERIOD, EXPM_TERMS = range(10)
TUNING_SIZE = 10


@kernel
def schedule_gains(link_inertia: np.ndarray, rotor: np.ndarray, stiffness: np.ndarray, damping: np.ndarray,
                   moving: np.ndarray, tuning: np.ndarray, iterations: int, p: np.ndarray, s: np.ndarray,
                   ad: np.ndarray, bd: np.ndarray, k: np.ndarray, l: np.ndarray) -> None:  # pragma: no cover - compiled
    """`schedule` after the link inertia matrix: `slow_joints_model`, `lqr_weights`, `noise_covariances`, then
    `iterations` Riccati iterations from p (the LQR's, 4m x 4m) and s (the filter's, 5m x 5m), both updated in
    place, and the gains: ad (5m x 5m) and bd (5m x 2m) the sampled model, k (m x 4m), l (5m x 2m)."""
    m = rotor.shape[0]
    period = tuning[PERIOD]
    # slow_joints_model: [A B; 0 0], its exponential by the series
    k_mat, d_mat, inv_rotor = np.diag(stiffness), np.diag(damping), np.diag(1.0 / rotor)
    inv_link = np.linalg.inv(link_inertia)
    a = np.zeros((7 * m, 7 * m))
    eye = np.eye(m)
    a[0:m, m : 2 * m] = eye
    a[2 * m : 3 * m, 3 * m : 4 * m] = eye
    a[m : 2 * m, 0:m] = -inv_rotor @ k_mat
    a[m : 2 * m, m : 2 * m] = -inv_rotor @ d_mat
    a[m : 2 * m, 2 * m : 3 * m] = inv_rotor @ k_mat
    a[m : 2 * m, 3 * m : 4 * m] = inv_rotor @ d_mat
    a[3 * m : 4 * m, 0:m] = inv_link @ k_mat
    a[3 * m : 4 * m, m : 2 * m] = inv_link @ d_mat
    a[3 * m : 4 * m, 2 * m : 3 * m] = -inv_link @ k_mat
    a[3 * m : 4 * m, 3 * m : 4 * m] = -inv_link @ d_mat
    for j in range(m):
        for i in range(m):
            a[3 * m + i, 4 * m + j] = inv_link[i, j] * (1.0 if moving[j] else 0.0)
            a[m + i, 4 * m + j] = inv_rotor[i, j] * (0.0 if moving[j] else 1.0)
    a[m : 2 * m, 5 * m : 6 * m] = inv_rotor
    a[3 * m : 4 * m, 6 * m :] = -inv_link
    a = a * period
    e, term = np.eye(7 * m), np.eye(7 * m)
    for i in range(1, int(tuning[EXPM_TERMS]) + 1):
        term = term @ a / i
        e = e + term
    ad[:, :] = e[: 5 * m, : 5 * m]
    bd[:, :] = e[: 5 * m, 5 * m :]
    # lqr_weights and noise_covariances
    w = tuning[BANDWIDTH]
    weights = np.zeros((4 * m, 4 * m))
    process = np.zeros((5 * m, 5 * m))
    measurement = np.zeros((2 * m, 2 * m))
    for j in range(m):
        whole = rotor[j] + link_inertia[j, j]
        angle, speed = (whole * w * w) ** 2, 0.5 * (whole * w) ** 2
        weights[j, j], weights[m + j, m + j] = tuning[MOTOR_WEIGHT] * angle, tuning[MOTOR_WEIGHT] * speed
        weights[2 * m + j, 2 * m + j], weights[3 * m + j, 3 * m + j] = angle, speed
        process[m + j, m + j] = (tuning[ROTOR_NOISE] / rotor[j]) ** 2 * period
        process[3 * m + j, 3 * m + j] = (tuning[LINK_NOISE] / link_inertia[j, j]) ** 2 * period
        process[4 * m + j, 4 * m + j] = (tuning[WALK] if moving[j] else tuning[REST_WALK]) ** 2 * period
        measurement[j, j] = tuning[ANGLE_NOISE] ** 2
        measurement[m + j, m + j] = tuning[SPEED_NOISE] ** 2
    # the Riccati iterations (the filter measures the rotors' angles and speeds: c = [I 0])
    a4, b4 = np.ascontiguousarray(ad[: 4 * m, : 4 * m]), np.ascontiguousarray(bd[: 4 * m, :m])
    ad_c = np.ascontiguousarray(ad)
    c = np.zeros((2 * m, 5 * m))
    c[:, : 2 * m] = np.eye(2 * m)
    r = np.eye(m)
    p_now, s_now = p.copy(), s.copy()
    for _ in range(iterations):
        bp = b4.T @ p_now
        gain = np.linalg.solve(r + bp @ b4, bp @ a4)
        p_now = weights + a4.T @ p_now @ (a4 - b4 @ gain)
        innovation = c @ s_now @ c.T + measurement
        s_now = ad_c @ (s_now - s_now @ c.T @ np.linalg.solve(innovation, c @ s_now)) @ ad_c.T + process
    p[:, :] = p_now
    s[:, :] = s_now
    bp = b4.T @ p_now
    k[:, :] = np.linalg.solve(r + bp @ b4, bp @ a4)
    l[:, :] = s_now @ c.T @ np.linalg.inv(c @ s_now @ c.T + measurement)
