"""The motion room's compiled kernels: the thermal, winding and gear-friction estimates' per-cycle updates (numba).

Each does the operations of its class's numpy code (its reference) in the same order: the same numbers.
"""

from __future__ import annotations

import numpy as np

from orc_rpl.plant.compiled import inlined_kernel, kernel


@inlined_kernel
def load_update(tau_nm: np.ndarray, gain: np.ndarray, decay: np.ndarray, load: np.ndarray) -> None:  # pragma: no cover
    """`ThermalModel.update` compiled: load = load decay + tau^2 gain, the same operations."""
    for j in range(load.shape[0]):
        load[j] = load[j] * decay[j] + (tau_nm[j] * tau_nm[j]) * gain[j]


@inlined_kernel
def rise_update(tau_nm: np.ndarray, gain: np.ndarray, gain_per_k: np.ndarray, decay: np.ndarray,
                rise: np.ndarray) -> None:  # pragma: no cover - compiled
    """`WindingTemperature.update`'s model part compiled: the same operations in the same order."""
    for j in range(rise.shape[0]):
        heat = rise[j] * gain_per_k[j] + gain[j]
        rise[j] = rise[j] * decay[j] + (tau_nm[j] * tau_nm[j]) * heat


@inlined_kernel
def sums_update(tau_nm: np.ndarray, qd_rad_s: np.ndarray, speed_sum: np.ndarray, speed_sq_sum: np.ndarray,
                tau_sq_sum: np.ndarray) -> None:  # pragma: no cover - compiled
    """`GearFriction.update`'s sums compiled: |qd|, qd^2 and tau^2 added in place, the same operations."""
    for j in range(speed_sum.shape[0]):
        speed = abs(qd_rad_s[j])
        speed_sum[j] = speed_sum[j] + speed
        speed_sq_sum[j] = speed_sq_sum[j] + speed * speed
        tau_sq_sum[j] = tau_sq_sum[j] + tau_nm[j] * tau_nm[j]


@kernel
def winding_sample(current_a: np.ndarray, voltage_v: np.ndarray, k: np.ndarray, speed_rad_s: np.ndarray,
                   rise_k: np.ndarray, sums: np.ndarray, flags: np.ndarray, calibrating: bool, correct: bool,
                   min_current_a: float, calibrate_below_k: float, calibration_min_a2: float, correction_a2: float,
                   tempco: float, ambient_c: float) -> bool:  # pragma: no cover - compiled
    """`WindingTemperature._sample` compiled: the same operations in the same order (sums: the calibration's
    numerator and denominator, the correction's; flags: calibrated, uncalibrated); returns `calibrating`."""
    n = rise_k.shape[0]
    ohm_a2, a2 = np.empty(n), np.empty(n)
    for j in range(n):
        c = current_a[j]
        i = c if abs(c) >= min_current_a else c * 0.0
        ohm_a2[j] = (voltage_v[j] - k[j] * speed_rad_s[j]) * i
        a2[j] = i * i
    if calibrating:
        calibrating = False
        for j in range(n):
            if not (flags[0, j] or flags[1, j]):
                rise = rise_k[j]
                if rise < calibrate_below_k:
                    sums[0, j] += ohm_a2[j] / (1.0 + tempco * (ambient_c + rise - 20.0))
                    sums[1, j] += a2[j]
                elif sums[1, j] >= calibration_min_a2:
                    flags[0, j] = True
                else:
                    flags[1, j] = True
            if not (flags[0, j] or flags[1, j]):
                calibrating = True
    for j in range(n):
        if flags[0, j]:
            sums[2, j] += ohm_a2[j]
            sums[3, j] += a2[j]
    if correct:
        for j in range(n):
            d = sums[3, j]
            if d > 0.0:
                cd = sums[1, j]
                r20 = sums[0, j] / (cd if cd > 0.0 else 1.0)
                rise = 20.0 + (sums[2, j] / d / r20 - 1.0) / tempco - ambient_c
                rise_k[j] += d / (d + correction_a2) * (rise - rise_k[j])
            sums[2, j] = 0.0
            sums[3, j] = 0.0
    return calibrating


@kernel
def cycle_update(tau_nm: np.ndarray, qd_rad_s: np.ndarray, load_gain: np.ndarray, load_decay: np.ndarray,
                 load: np.ndarray, rise_gain: np.ndarray, rise_gain_per_k: np.ndarray, rise_decay: np.ndarray,
                 rise: np.ndarray, speed_sum: np.ndarray, speed_sq_sum: np.ndarray,
                 tau_sq_sum: np.ndarray) -> None:  # pragma: no cover - compiled
    """`load_update`, `rise_update` and `sums_update` in one call (the motion cycle's three estimates: one
    dispatch from Python; numba puts the three bodies in here, they are `inlined_kernel`s)."""
    load_update(tau_nm, load_gain, load_decay, load)
    rise_update(tau_nm, rise_gain, rise_gain_per_k, rise_decay, rise)
    sums_update(tau_nm, qd_rad_s, speed_sum, speed_sq_sum, tau_sq_sum)
