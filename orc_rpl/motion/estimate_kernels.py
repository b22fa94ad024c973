"""The motion room's compiled kernels: the thermal, winding and gear-friction estimates' per-cycle updates (numba).

Each does the operations of its class's numpy code (its reference) in the same order: the same numbers.
"""

from __future__ import annotations

import numpy as np

from orc_rpl.plant.compiled import kernel


@kernel
def load_update(tau_nm: np.ndarray, gain: np.ndarray, decay: np.ndarray, load: np.ndarray) -> None:  # pragma: no cover
    """`ThermalModel.update` compiled: load = load decay + tau^2 gain, the same operations."""
    for j in range(load.shape[0]):
        load[j] = load[j] * decay[j] + (tau_nm[j] * tau_nm[j]) * gain[j]


@kernel
def rise_update(tau_nm: np.ndarray, gain: np.ndarray, gain_per_k: np.ndarray, decay: np.ndarray,
                rise: np.ndarray) -> None:  # pragma: no cover - compiled
    """`WindingTemperature.update`'s model part compiled: the same operations in the same order."""
    for j in range(rise.shape[0]):
        heat = rise[j] * gain_per_k[j] + gain[j]
        rise[j] = rise[j] * decay[j] + (tau_nm[j] * tau_nm[j]) * heat


@kernel
def sums_update(tau_nm: np.ndarray, qd_rad_s: np.ndarray, speed_sum: np.ndarray, speed_sq_sum: np.ndarray,
                tau_sq_sum: np.ndarray) -> None:  # pragma: no cover - compiled
    """`GearFriction.update`'s sums compiled: |qd|, qd^2 and tau^2 added in place, the same operations."""
    for j in range(speed_sum.shape[0]):
        speed = abs(qd_rad_s[j])
        speed_sum[j] = speed_sum[j] + speed
        speed_sq_sum[j] = speed_sq_sum[j] + speed * speed
        tau_sq_sum[j] = tau_sq_sum[j] + tau_nm[j] * tau_nm[j]
