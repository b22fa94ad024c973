"""The arm-control room's compiled kernel: the path velocity controller's admissible range of s'' (numba)."""

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
