"""The plant room's drive call compiled: set-points in, mj_step a row, the copper losses and what the servo measures out."""

from __future__ import annotations

import numpy as np

from orc_rpl.plant.compiled import inlined_kernel, kernel, mj_step_intrinsic

step = mj_step_intrinsic()


@kernel
def drive_rows(model_address: int, data_address: int, position_rows: np.ndarray, velocity_rows: np.ndarray,
               ff_rows: np.ndarray, ctrl: np.ndarray, force: np.ndarray, squares: np.ndarray,
               tau_sq_sum: np.ndarray) -> None:  # pragma: no cover - compiled (tests/plant/test_kernels.py)
    """`PidDrives.drive` without its callbacks: a row of the drives' inputs a step, then mj_step, for
    len(position_rows) steps; the squared forces of the steps summed into tau_sq_sum (the copper
    losses, `RealisticCell._copper_rows`: the same sums in the same order). `squares`: work array."""
    n_steps, n = position_rows.shape
    for i in range(n_steps):
        for j in range(n):
            ctrl[3 * j] = position_rows[i, j]
            ctrl[3 * j + 1] = velocity_rows[i, j]
            ctrl[3 * j + 2] = ff_rows[i, j]
        step(model_address, data_address)
        for j in range(n):
            f = force[j]
            squares[j] = f * f if i == 0 else squares[j] + f * f
    for j in range(n):
        tau_sq_sum[j] = tau_sq_sum[j] + squares[j]


@inlined_kernel
def measure(qpos: np.ndarray, qvel: np.ndarray, qpos_address: np.ndarray, qvel_address: np.ndarray,
            noise_row: np.ndarray, count_per_rad: float, rad_per_count: float, q_meas: np.ndarray,
            qd_meas: np.ndarray) -> None:  # pragma: no cover - compiled
    """`RealisticCell._measure`: the encoder's counts (rounded half to even, as numpy's rint) and the noisy speed."""
    for j in range(q_meas.shape[0]):
        q_meas[j] = np.rint(qpos[qpos_address[j]] * count_per_rad) * rad_per_count
        qd_meas[j] = qvel[qvel_address[j]] + noise_row[j]


@kernel
def winding_sample(force: np.ndarray, k_amp: np.ndarray, r_ohm: np.ndarray, rise_k: np.ndarray, ambient_c: float,
                   tempco_1_k: float, qvel: np.ndarray, qvel_address: np.ndarray, qd_meas: np.ndarray,
                   noise: np.ndarray, voltage_noise: float, current_noise: float,
                   out: np.ndarray) -> None:  # pragma: no cover - compiled
    """`RealisticCell.winding_measurement` compiled (the noise drawn by the caller): rows of `out` are the
    terminal voltage, the current and the speed the servo reads; the same operations in the same order."""
    for j in range(out.shape[1]):
        current = force[j] / k_amp[j]
        resistance = r_ohm[j] * (1.0 + tempco_1_k * ((ambient_c + rise_k[j]) - 20.0))
        voltage = resistance * current + k_amp[j] * qvel[qvel_address[j]]
        out[0, j] = voltage + voltage_noise * noise[0, j]
        out[1, j] = current + current_noise * noise[1, j]
        out[2, j] = qd_meas[j]


@kernel
def heat(tau_sq_sum: np.ndarray, n_steps: int, every_steps: int, w_decay: np.ndarray, g_decay: float,
         r_ohm: np.ndarray, k_amp: np.ndarray, w_rth: np.ndarray, g_rth: np.ndarray, tempco_1_k: float,
         ambient_c: float, heat_share: float, cold_factor: float, warm_rise_k: float, rise_k: np.ndarray,
         gear_rise_k: np.ndarray, coulomb_now: np.ndarray, viscous_now: np.ndarray, coulomb: np.ndarray,
         viscous: np.ndarray, qvel: np.ndarray, qvel_address: np.ndarray, brake_nm: np.ndarray, braked: bool,
         dof_damping: np.ndarray, dof_frictionloss: np.ndarray, new: np.ndarray) -> None:  # pragma: no cover
    """`RealisticCell._heat` and `_apply_friction` compiled: windings and gearboxes over the last n_steps
    steps, the friction that follows written into the model; the new winding rise, gear rise, Coulomb
    and viscous friction into the rows of `new` (the same operations in the same order)."""
    g = g_decay if n_steps == every_steps else g_decay ** (n_steps / every_steps)
    for j in range(tau_sq_sum.shape[0]):
        w = w_decay[j] if n_steps == every_steps else w_decay[j] ** (n_steps / every_steps)
        mean_tau_sq = tau_sq_sum[j] / n_steps
        tau_sq_sum[j] = 0.0
        resistance = r_ohm[j] * (1.0 + tempco_1_k * ((ambient_c + rise_k[j]) - 20.0))
        copper_w = resistance * mean_tau_sq / (k_amp[j] * k_amp[j])
        new[0, j] = w * rise_k[j] + (1.0 - w) * w_rth[j] * copper_w
        qd = abs(qvel[qvel_address[j]])
        heat_w = coulomb_now[j] * qd + viscous_now[j] * qd * qd + heat_share * copper_w
        gear = g * gear_rise_k[j] + (1.0 - g) * g_rth[j] * heat_w
        new[1, j] = gear
        factor = 1.0 + (cold_factor - 1.0) * np.exp(-gear / warm_rise_k)
        new[2, j], new[3, j] = coulomb[j] * factor, viscous[j] * factor
        dof_damping[qvel_address[j]] = new[3, j]
        dof_frictionloss[qvel_address[j]] = new[2, j] + brake_nm[j] if braked else new[2, j]
