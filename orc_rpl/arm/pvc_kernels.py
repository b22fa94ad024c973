"""The arm-control room's compiled kernel: the path velocity controller's admissible range of s'' (numba)."""

from __future__ import annotations

import math

import numpy as np

from orc_rpl.plant.compiled import kernel


@kernel
def admissible_range(b1: np.ndarray, b2: np.ndarray, limit: np.ndarray) -> tuple[float, float]:  # pragma: no cover
    """`PathVelocityController.admissible`'s range from b1, b2 compiled (the same operations, exact)."""
    lo, hi = -math.inf, math.inf
    for j in range(b1.shape[0]):
        if abs(b1[j]) >= 1e-9:   # a joint the path acceleration does not move sets no bound
            r1, r2 = (-limit[j] - b2[j]) / b1[j], (limit[j] - b2[j]) / b1[j]
            lo = max(lo, min(r1, r2))
            hi = min(hi, max(r1, r2))
    return lo, hi


@kernel
def admissible_range_sum(b1: np.ndarray, b2: np.ndarray, b2_extra: np.ndarray,
                         limit: np.ndarray) -> tuple[float, float]:  # pragma: no cover
    """`admissible_range` with b2 given as two terms (b2 + b2_extra, summed here as numpy would: the same numbers)."""
    lo, hi = -math.inf, math.inf
    for j in range(b1.shape[0]):
        if abs(b1[j]) >= 1e-9:
            b2j = b2[j] + b2_extra[j]
            r1, r2 = (-limit[j] - b2j) / b1[j], (limit[j] - b2j) / b1[j]
            lo = max(lo, min(r1, r2))
            hi = min(hi, max(r1, r2))
    return lo, hi
