"""The motion room's compiled spline kernel: a joint path's values and first two derivatives at once (numba).

It does what scipy's PPoly evaluation does (`scipy/interpolate/_ppoly.pyx`: `find_interval_ascending`,
`evaluate_poly1`), in the same order of operations: the same numbers as `CubicSpline(x, nu)`.
"""

from __future__ import annotations

import numpy as np

from orc_rpl.plant.compiled import kernel


@kernel
def spline_orders(breaks: np.ndarray, c: np.ndarray, x: np.ndarray) -> np.ndarray:  # pragma: no cover - compiled
    """(3, len(x), n): the piecewise polynomial (coefficients c (k, m, n), highest power first, as PPoly keeps
    them) and its first two derivatives at the points x, extrapolated from the end pieces."""
    k, m, n = c.shape
    out = np.empty((3, x.shape[0], n))
    last = breaks.shape[0] - 2
    for p in range(x.shape[0]):
        xval = x[p]
        # the piece: breaks[i] <= xval < breaks[i + 1], the end pieces extrapolating (the last one closed)
        lo, hi = 0, last
        if xval >= breaks[last]:
            lo = last
        elif xval >= breaks[1]:
            while hi - lo > 1:   # breaks[lo] <= xval < breaks[hi]
                mid = (lo + hi) // 2
                if xval < breaks[mid]:
                    hi = mid
                else:
                    lo = mid
        i = lo
        s = xval - breaks[i]
        for dx in range(3):
            for j in range(n):
                res = 0.0
                z = 1.0
                for kp in range(k):
                    if kp < dx:
                        continue
                    prefactor = 1.0
                    for f in range(kp, kp - dx, -1):
                        prefactor *= f
                    res = res + c[k - kp - 1, i, j] * z * prefactor
                    if kp < k - 1 and kp >= dx:
                        z *= s
                out[dx, p, j] = res
    return out
