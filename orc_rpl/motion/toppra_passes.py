"""TOPP-RA's two passes (toppra's ReachabilityAlgorithm) with the Python around each stage's solve made lean.

toppra's `compute_controllable_sets`, `_one_step`, `compute_parameterization` and TOPPRA's `_forward_step` build
new numpy arrays and test them at every grid point: two thirds of a pass's time with the seidel solver (its
solves are compiled). `lean_toppra(toppra)` subclasses toppra's TOPPRA class with the same passes: the same
solver calls with the same arguments in the same order (the seidel solver's warm start depends on that order),
the same clamps and the same retries (toppra 0.6's code, constants from toppra.constants); only the bookkeeping
is plain Python floats. The result is toppra's, bit for bit (tests/motion/test_toppra_passes.py compares them).
The module does not import toppra: timing.py, the one module that does, hands it over.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np


def lean_toppra(toppra: Any) -> type:
    """toppra's TOPPRA class with the lean passes (toppra: the imported package)."""
    from_constants = toppra.constants
    tiny, small, max_tries = from_constants.TINY, from_constants.SMALL, from_constants.MAX_TRIES
    codes = toppra.algorithm.algorithm.ParameterizationReturnCode
    nan = math.nan

    class LeanTOPPRA(toppra.algorithm.TOPPRA):  # type: ignore[misc, name-defined]
        """TOPPRA with `compute_controllable_sets` and `compute_parameterization` as toppra's, leaner."""

        def compute_controllable_sets(self, sdmin: float, sdmax: float) -> np.ndarray:
            assert sdmin <= sdmax and 0 <= sdmin
            n = self._N
            solve = self.solver_wrapper.solve_stagewise_optim
            upper, lower = np.array([1e-9, -1.0]), np.array([-1e-9, 1.0])  # _one_step's g_upper and -g_upper
            rows = [[0.0, 0.0] for _ in range(n + 1)]
            rows[n] = [sdmin**2, sdmax**2]
            self.solver_wrapper.setup_solver()
            for i in range(n - 1, -1, -1):
                k_lo, k_hi = rows[i + 1]
                if math.isnan(k_lo) or math.isnan(k_hi):
                    lo = hi = nan
                else:  # _one_step: the largest x, then the least, reaching [k_lo, k_hi] from stage i
                    hi = solve(i, None, upper, nan, nan, k_lo, k_hi)[1]
                    lo = solve(i, None, lower, nan, nan, k_lo, k_hi)[1]
                if lo < 0:
                    lo = 0.0
                rows[i] = [lo, hi]
                if math.isnan(lo) or math.isnan(hi):
                    out = np.zeros((n + 1, 2))
                    out[i:] = rows[i:]
                    return out  # as toppra: the sets computed so far, the rest zeros
            self.solver_wrapper.close_solver()
            return np.array(rows, dtype=float)

        def compute_parameterization(self, sd_start: float, sd_end: float, return_data: bool = False) -> tuple:
            if sd_end < 0 or sd_start < 0:
                raise toppra.exceptions.BadInputVelocities(
                    f"Negative path velocities: path velocities must be positive: ({sd_start}, {sd_end})")
            K = self.compute_controllable_sets(sd_end, sd_end)
            if np.isnan(K).any():
                self._problem_data.return_code = codes.FailUncontrollable
                return (None, None, None, K) if return_data else (None, None, None)
            self._problem_data.K = K
            x_start = sd_start**2
            if x_start + small < K[0, 0] or K[0, 1] + small < x_start:
                self._problem_data.return_code = codes.FailUncontrollable
                return (None, None, None, K) if return_data else (None, None, None)
            wrapper = self.solver_wrapper
            n = wrapper.get_no_stages()
            deltas = wrapper.get_deltas().tolist()
            k_rows = K.tolist()
            xs, us = [0.0] * (n + 1), [0.0] * n
            xs[0] = x_start
            g = np.array([0.0, -1.0])
            solve = wrapper.solve_stagewise_optim
            tries = 0
            wrapper.setup_solver()
            i = 0
            while i < self._N:
                x = xs[i]
                if math.isnan(x):
                    u = nan
                else:
                    g[0] = -2 * deltas[i]  # TOPPRA._forward_step's g_upper
                    u = solve(i, None, g, x, x, k_rows[i + 1][0], k_rows[i + 1][1])[0]
                if math.isnan(u):
                    if tries < max_tries:
                        xs[i] = max(x - tiny, 0.999 * x)
                        tries += 1
                    else:
                        for j in range(i + 1, n + 1):
                            xs[j] = nan
                        break
                else:
                    tries = 0
                    us[i] = u
                    x_next = x + 2 * deltas[i] * u
                    x_next = max(x_next - tiny, 0.9999 * x_next)
                    xs[i + 1] = min(k_rows[i + 1][1], max(k_rows[i + 1][0], x_next))
                    i += 1
            wrapper.close_solver()
            sd_vec = np.sqrt(np.array(xs, dtype=float))
            sdd_vec = np.array(us, dtype=float)
            v_vec = np.zeros((n, wrapper.get_no_vars() - 2))
            self._problem_data.sd_vec = sd_vec
            self._problem_data.sdd_vec = sdd_vec
            self._problem_data.return_code = codes.ErrUnknown if np.isnan(sd_vec).any() else codes.Ok
            return (sdd_vec, sd_vec, v_vec, K) if return_data else (sdd_vec, sd_vec, v_vec)

    return LeanTOPPRA
