"""The motion room's TOPP-RA passes compiled: toppra's seidel solver and both passes of toppra_passes.py in numba.

toppra's `seidelWrapper` (Cython) solves a two-variable LP per grid point; toppra_passes.py's lean
passes call it from Python, some 3 N times a plan. Here the stage's LP (`cy_solve_lp2d`, or
`cy_solve_lp1d` where x is fixed, as toppra 0.6 solves the forward pass) and the two passes around
it are one kernel each: the same operations in the same order, the same warm start (the last active
constraints of the upper and of the lower solver), the same clamps and retries, so the profiles are
toppra's (tests/motion/test_toppra_kernels.py compares them with toppra's seidel solver and passes,
the reference). The LP's coefficients are the wrapper's: `stage_rows` builds them from the
constraints' parameters as toppra's wrapper does, in numpy.
"""

from __future__ import annotations

import math

import numpy as np

from orc_rpl.plant.compiled import inlined_kernel, kernel

#: toppra's seidel constants (cy_seidel_solverwrapper.pyx): feasibility slack, parallel-line slack, the bounds on
#: u and x, and the 1-D subproblem's bounds (never active)
TINY, SMALL, VAR_MIN, VAR_MAX, INF = 1e-10, 1e-8, -100000000.0, 100000000.0, 10000000000.0
#: entries of a pass's `state` (int64): the upper and the lower solver's warm start (two constraint indices each)
UP0, UP1, DOWN0, DOWN1 = range(4)


def stage_rows(params: list[tuple], n_stages: int) -> tuple[np.ndarray, ...]:
    """(a, b, c, low, high): toppra seidelWrapper's LP rows of each grid point from the constraints' parameters
    (`compute_constraint_params` of each, all canonical linear and `identical`), the same numpy operations; the
    first two columns of a, b, c are the next stage's bounds, set per solve."""
    count = 2 + sum(p[3].shape[0] for p in params if p[0] is not None)
    a, b, c = np.zeros((n_stages + 1, count)), np.zeros((n_stages + 1, count)), np.zeros((n_stages + 1, count))
    low, high = np.ones((n_stages + 1, 2)) * VAR_MIN, np.ones((n_stages + 1, 2)) * VAR_MAX
    at = 2
    for a_j, b_j, c_j, f_j, h_j, u_bound, x_bound in params:
        if a_j is not None:
            rows = f_j.shape[0]
            a[:, at : at + rows] = a_j.dot(f_j.T)
            b[:, at : at + rows] = b_j.dot(f_j.T)
            c[:, at : at + rows] = c_j.dot(f_j.T) - h_j
            at += rows
        if u_bound is not None:
            low[:, 0], high[:, 0] = np.maximum(low[:, 0], u_bound[:, 0]), np.minimum(high[:, 0], u_bound[:, 1])
        if x_bound is not None:
            low[:, 1], high[:, 1] = np.maximum(low[:, 1], x_bound[:, 0]), np.minimum(high[:, 1], x_bound[:, 1])
    return a, b, c, low, high


@inlined_kernel
def lp1d(v0: float, rows: int, a: np.ndarray, b: np.ndarray, low: float,
         high: float) -> tuple[bool, float, int]:  # pragma: no cover - compiled
    """`cy_solve_lp1d`: max v0 x subject to a x + b <= 0 (the first `rows` rows), low <= x <= high; (feasible, x,
    the active row: -1 low, -2 high)."""
    cur_min, cur_max, active_min, active_max = low, high, -1, -2
    for i in range(rows):
        if a[i] > TINY:
            x = -b[i] / a[i]
            if x < cur_max:
                cur_max, active_max = x, i
        elif a[i] < -TINY:
            x = -b[i] / a[i]
            if x > cur_min:
                cur_min, active_min = x, i
    if cur_min > cur_max:
        return False, 0.0, 0
    if abs(v0) < TINY or v0 < 0:
        return True, cur_min, active_min
    return True, cur_max, active_max


@inlined_kernel
def lp2d(v0: float, v1: float, a: np.ndarray, b: np.ndarray, c: np.ndarray, low0: float, low1: float, high0: float,
         high1: float, warm: np.ndarray, at: int, index_map: np.ndarray, a_1d: np.ndarray,
         b_1d: np.ndarray) -> tuple[bool, float, float, int, int]:  # pragma: no cover - compiled
    """`cy_solve_lp2d`: max v0 u + v1 x subject to a u + b x + c <= 0 and the box; (feasible, u, x, the two active
    constraints). warm[at], warm[at + 1]: the rows likely active (the warm start), tried first."""
    rows = a.shape[0]
    low, high = (low0, low1), (high0, high1)
    if low0 > high0 or low1 > high1:
        return False, 0.0, 0.0, 0, 0
    if v0 > TINY:
        opt0, active0 = high0, -2
    else:
        opt0, active0 = low0, -1
    if v1 > TINY:
        opt1, active1 = high1, -4
    else:
        opt1, active1 = low1, -3
    w0, w1 = warm[at], warm[at + 1]
    if 0 <= w0 < rows and 0 <= w1 < rows and w0 != w1:
        index_map[0], index_map[1] = w1, w0
        row = 2
        for i in range(rows):
            if i != w0 and i != w1:
                index_map[row] = i
                row += 1
    else:
        for i in range(rows):
            index_map[i] = i
    for k in range(rows):
        i = index_map[k]
        if a[i] * opt0 + b[i] * opt1 + c[i] < TINY:
            continue
        active0 = i
        norm = a[i] ** 2 + b[i] ** 2
        zero0, zero1 = -a[i] * c[i] / norm, -b[i] * c[i] / norm
        tan0, tan1 = -b[i], a[i]
        v_1d = tan0 * v0 + tan1 * v1
        rows_1d = 4 + k
        for j in range(rows_1d):
            if j == k:
                aj, bj, cj = -1.0, 0.0, low[0]
            elif j == k + 1:
                aj, bj, cj = 1.0, 0.0, -high[0]
            elif j == k + 2:
                aj, bj, cj = 0.0, -1.0, low[1]
            elif j == k + 3:
                aj, bj, cj = 0.0, 1.0, -high[1]
            else:
                aj, bj, cj = a[index_map[j]], b[index_map[j]], c[index_map[j]]
            denom = tan0 * aj + tan1 * bj
            if denom > TINY:
                limit = -(cj + zero1 * bj + zero0 * aj) / denom
                a_1d[j], b_1d[j] = 1.0, -limit
            elif denom < -TINY:
                limit = -(cj + zero1 * bj + zero0 * aj) / denom
                a_1d[j], b_1d[j] = -1.0, limit
            else:   # parallel to the base line: infeasible, or 0 <= 1
                if cj + zero1 * bj + zero0 * aj > SMALL:
                    return False, 0.0, 0.0, 0, 0
                a_1d[j], b_1d[j] = 0.0, -1.0
        feasible, t, active = lp1d(v_1d, rows_1d, a_1d, b_1d, -INF, INF)
        if not feasible:
            return False, 0.0, 0.0, 0, 0
        opt0, opt1 = zero0 + t * tan0, zero1 + t * tan1
        if active < k:
            active1 = index_map[active]
        elif active <= k + 3:
            active1 = -1 - (active - k)
        else:   # the 1-D subproblem's own bound: toppra calls it a failure
            return False, 0.0, 0.0, 0, 0
    return True, opt0, opt1, active0, active1


@inlined_kernel
def solve_stage(i: int, g0: float, g1: float, x_min: float, x_max: float, x_next_min: float, x_next_max: float,
                a: np.ndarray, b: np.ndarray, c: np.ndarray, low: np.ndarray, high: np.ndarray, deltas: np.ndarray,
                warm: np.ndarray, index_map: np.ndarray, a_1d: np.ndarray, b_1d: np.ndarray,
                bx_c: np.ndarray) -> tuple[float, float]:  # pragma: no cover - compiled
    """`seidelWrapper.solve_stagewise_optim(i, None, (g0, g1), x_min, x_max, x_next_min, x_next_max)` with
    solve_lp1d (toppra's TOPPRA): (u, x), NaN where infeasible; the stage's first two rows and `warm` updated as
    toppra's wrapper updates its own."""
    n = deltas.shape[0]
    low0, low1, high0, high1 = low[i, 0], low[i, 1], high[i, 0], high[i, 1]
    if not math.isnan(x_min):
        low1 = max(low1, x_min)
    if not math.isnan(x_max):
        high1 = min(high1, x_max)
    if i < n:
        if math.isnan(x_next_min):
            a[i, 0], b[i, 0], c[i, 0] = 0.0, 0.0, -1.0
        else:
            a[i, 0], b[i, 0], c[i, 0] = -2 * deltas[i], -1.0, x_next_min
        if math.isnan(x_next_max):
            a[i, 1], b[i, 1], c[i, 1] = 0.0, 0.0, -1.0
        else:
            a[i, 1], b[i, 1], c[i, 1] = 2 * deltas[i], 1.0, -x_next_max
    else:
        for k in range(2):
            a[i, k], b[i, k], c[i, k] = 0.0, 0.0, -1.0
    v0, v1 = -g0, -g1
    if x_min == x_max:   # x fixed: the 1-D LP in u
        rows = a.shape[1]
        for k in range(rows):
            bx_c[k] = b[i, k] * x_min + c[i, k]
        feasible, u, active = lp1d(v0, rows, a[i], bx_c, low0, high0)
        if not feasible:
            return math.nan, math.nan
        warm[UP0 if g1 > 0 else DOWN0] = active
        return u, x_min
    at = UP0 if g1 > 0 else DOWN0
    feasible, u, x, active0, active1 = lp2d(v0, v1, a[i], b[i], c[i], low0, low1, high0, high1, warm, at, index_map,
                                            a_1d, b_1d)
    if not feasible:
        return math.nan, math.nan
    warm[at], warm[at + 1] = active0, active1
    return u, x


@kernel
def controllable_sets(sd_min: float, sd_max: float, a: np.ndarray, b: np.ndarray, c: np.ndarray, low: np.ndarray,
                      high: np.ndarray, deltas: np.ndarray, warm: np.ndarray, out: np.ndarray) -> None:  # pragma: no cover
    """toppra_passes' `compute_controllable_sets` into out ((N + 1) x 2, zeros beyond the first NaN set, as toppra)."""
    n, rows = deltas.shape[0], a.shape[1]
    index_map, a_1d, b_1d, bx_c = np.zeros(rows, dtype=np.int64), np.zeros(rows + 4), np.zeros(rows + 4), np.zeros(rows)
    out[:, :] = 0.0
    out[n, 0], out[n, 1] = sd_min ** 2, sd_max ** 2
    for i in range(n - 1, -1, -1):
        k_lo, k_hi = out[i + 1, 0], out[i + 1, 1]
        if math.isnan(k_lo) or math.isnan(k_hi):
            lo = hi = math.nan
        else:   # the largest x, then the least, reaching [k_lo, k_hi] from stage i
            hi = solve_stage(i, 1e-9, -1.0, math.nan, math.nan, k_lo, k_hi, a, b, c, low, high, deltas, warm,
                             index_map, a_1d, b_1d, bx_c)[1]
            lo = solve_stage(i, -1e-9, 1.0, math.nan, math.nan, k_lo, k_hi, a, b, c, low, high, deltas, warm,
                             index_map, a_1d, b_1d, bx_c)[1]
        if lo < 0:
            lo = 0.0
        out[i, 0], out[i, 1] = lo, hi
        if math.isnan(lo) or math.isnan(hi):
            return


@kernel
def forward_pass(x_start: float, sets: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray, low: np.ndarray,
                 high: np.ndarray, deltas: np.ndarray, warm: np.ndarray, tiny: float, max_tries: int, xs: np.ndarray,
                 us: np.ndarray) -> None:  # pragma: no cover - compiled
    """toppra_passes' `compute_parameterization` after the sets: the greedy forward pass from x_start into xs
    (N + 1) and us (N), with toppra's retries (`max_tries`, stepping x down by `tiny`) and clamps; NaN after a
    stage that fails."""
    n, rows = deltas.shape[0], a.shape[1]
    index_map, a_1d, b_1d, bx_c = np.zeros(rows, dtype=np.int64), np.zeros(rows + 4), np.zeros(rows + 4), np.zeros(rows)
    xs[:] = 0.0
    us[:] = 0.0
    xs[0] = x_start
    tries, i = 0, 0
    while i < n:
        x = xs[i]
        if math.isnan(x):
            u = math.nan
        else:
            u = solve_stage(i, -2 * deltas[i], -1.0, x, x, sets[i + 1, 0], sets[i + 1, 1], a, b, c, low, high,
                            deltas, warm, index_map, a_1d, b_1d, bx_c)[0]
        if math.isnan(u):
            if tries < max_tries:
                xs[i] = max(x - tiny, 0.999 * x)
                tries += 1
            else:
                for j in range(i + 1, n + 1):
                    xs[j] = math.nan
                break
        else:
            tries = 0
            us[i] = u
            x_next = x + 2 * deltas[i] * u
            x_next = max(x_next - tiny, 0.9999 * x_next)
            xs[i + 1] = min(sets[i + 1, 1], max(sets[i + 1, 0], x_next))
            i += 1
