"""The arm-control room's compiled kernels: the path velocity controller's admissible range of s'' and its time-scaled
motion cycle (numba)."""

from __future__ import annotations

import math

import numpy as np

from orc_rpl.plant.compiled import inlined_kernel, kernel


@inlined_kernel
def admissible_range_sum(b1: np.ndarray, b2: np.ndarray, b2_extra: np.ndarray | None,
                         limit: np.ndarray) -> tuple[float, float]:  # pragma: no cover
    """`PathVelocityController.admissible`'s range from b1, b2 compiled (the same operations, exact), b2 given
    as two terms (b2 + b2_extra, summed here as numpy would: the same numbers) or, with b2_extra None, as one
    (numba decides the `is None` test of an argument when it compiles: no add is left in that form)."""
    lo, hi = -math.inf, math.inf
    for j in range(b1.shape[0]):
        if abs(b1[j]) >= 1e-9:   # a joint the path acceleration does not move sets no bound
            b2j = b2[j]
            if b2_extra is not None:
                b2j = b2j + b2_extra[j]
            r1, r2 = (-limit[j] - b2j) / b1[j], (limit[j] - b2j) / b1[j]
            lo = max(lo, min(r1, r2))
            hi = min(hi, max(r1, r2))
    return lo, hi


@kernel
def admissible_range(b1: np.ndarray, b2: np.ndarray, limit: np.ndarray) -> tuple[float, float]:  # pragma: no cover
    """`admissible_range_sum` with b2 in one term (its own entry point: a call from Python with three arrays is
    the dispatcher's fast path, a None argument is not; numba puts admissible_range_sum's body in here)."""
    return admissible_range_sum(b1, b2, None, limit)


@inlined_kernel
def _first_min(a: float, b: float) -> float:  # pragma: no cover - compiled
    """Python's min(a, b): b only when it is smaller (the first of equals, as the reference)."""
    return b if b < a else a


@inlined_kernel
def _first_max(a: float, b: float) -> float:  # pragma: no cover - compiled
    """Python's max(a, b): b only when it is larger."""
    return b if b > a else a


@kernel
def scaled_profile(x: float, sd: float, t_cycle: float, x_n: float, sd_n: float, sdd_n: float, lo: float, hi: float,
                   end_x: float, nominal_ended: bool, kv: float, kp: float, overspeed: float, x_mono: np.ndarray,
                   sd_mono: np.ndarray, h: float, stop_decel_min: float, brake_share: float, xs: np.ndarray,
                   sds: np.ndarray) -> tuple[float, bool]:  # pragma: no cover - compiled
    """`PathVelocityController._profile` compiled (its Python is the reference): the same operations in the same
    order; xs and sds (the cycle's servo steps) filled in; returns (s'', whether the wanted s'' was changed)."""
    remaining = end_x - x
    braking = False
    a_stop = 0.0
    if nominal_ended:
        a_stop = 0.5 * _first_max(-lo, stop_decel_min)
        braking = sd * sd >= 2.0 * a_stop * remaining
        wanted = -sd * sd / (2.0 * remaining) if braking else (math.sqrt(2.0 * a_stop * remaining) - sd) / t_cycle
    else:
        wanted = sdd_n + kv * (sd_n - sd) + kp * (x_n - x)
        x_ahead = _first_min(x + sd * t_cycle, end_x)
        wanted = _first_max(wanted, (np.interp(x_ahead, x_mono, sd_mono) - sd) / t_cycle)
    if braking:
        sdd = wanted
    elif lo <= hi:
        sdd = _first_min(_first_max(wanted, lo), hi)
    else:
        sdd = 0.5 * (lo + hi)
    changed = sdd != wanted
    x_next = _first_min(x + sd * t_cycle + 0.5 * sdd * t_cycle * t_cycle, end_x)
    if braking or nominal_ended and x_next >= end_x:
        bound = math.inf
    elif nominal_ended:
        bound = math.sqrt(2.0 * a_stop * (end_x - x_next))
    else:
        bound = (1.0 + overspeed) * np.interp(x_next, x_mono, sd_mono)
        bound = _first_min(bound, math.sqrt(2.0 * brake_share * _first_max(-lo, stop_decel_min) * (end_x - x_next)))
    if sd + sdd * t_cycle > bound:
        sdd = (bound - sd) / t_cycle
    if sd + sdd * t_cycle <= 0.0 and x_next < end_x:
        sdd = _first_min(_first_max(wanted, stop_decel_min), bound / t_cycle) if sd <= 0.0 else -sd / t_cycle
    stop_tau = sd / -sdd if sdd < 0.0 else math.inf
    for r in range(xs.shape[0]):
        tau = float(r + 1) * h
        if sdd < 0.0 and not tau <= stop_tau:   # np.minimum: the first unless the second is smaller (or NaN)
            tau = stop_tau
        xr = x + sd * tau + 0.5 * sdd * tau * tau
        xs[r] = xr if xr <= end_x or xr != xr else end_x
        sr = sd + sdd * tau
        sds[r] = sr if sr >= 0.0 or sr != sr else 0.0
    return sdd, changed


@kernel
def path_rates(d1: np.ndarray, d2: np.ndarray, sds: np.ndarray, sdd: float, qd: np.ndarray,
               qdd: np.ndarray) -> None:  # pragma: no cover - compiled
    """qd = f'(x) s' and qdd = f''(x) s'^2 + f'(x) s'' (s'' only while moving) at the cycle's servo steps, the
    operations of `PathVelocityController._scaled`'s numpy lines."""
    for r in range(sds.shape[0]):
        s = sds[r]
        s2 = s * s
        acc = sdd if s > 0.0 else 0.0
        for j in range(d1.shape[1]):
            qdd[r, j] = d2[r, j] * s2 + d1[r, j] * acc
            qd[r, j] = d1[r, j] * s
