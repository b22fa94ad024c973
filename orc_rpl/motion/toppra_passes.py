"""TOPP-RA's two passes (toppra's ReachabilityAlgorithm) with the Python around each stage's solve made lean.

toppra's `compute_controllable_sets`, `_one_step`, `compute_parameterization` and TOPPRA's `_forward_step` build
new numpy arrays and test them at every grid point: two thirds of a pass's time with the seidel solver (its
solves are compiled). `lean_toppra(toppra)` subclasses toppra's TOPPRA class with the same passes: the same
solver calls with the same arguments in the same order (the seidel solver's warm start depends on that order),
the same clamps and the same retries (toppra 0.6's code, constants from toppra.constants); only the bookkeeping
is plain Python floats. The result is toppra's, bit for bit (tests/motion/test_toppra_passes.py compares them).
Where numba is, the passes are compiled by default (COMPILED_PASSES): the seidel solver and both passes are
kernels (motion/toppra_kernels.py) on the LP rows toppra's wrapper would build, and toppra's wrapper is not
made; the lean Python passes on toppra's solver are their reference (tests/motion/test_toppra_kernels.py).
The module does not import toppra: timing.py, the one module that does, hands it over.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from orc_rpl.plant import compiled

#: Run the passes compiled (motion/toppra_kernels.py) where numba is; False: the lean Python passes on toppra's
#: seidel solver (the reference; read at each plan, so tests and benchmarks may switch it).
COMPILED_PASSES = True


class CompiledSeidel:
    """The compiled passes' solver wrapper: the LP rows of every grid point as toppra's seidelWrapper builds them
    (toppra_kernels.stage_rows) and its warm start, kept across both passes and a retry, as toppra keeps its own.
    It serves the two passes only: toppra's other uses of its wrapper (the feasible and reachable sets, which
    nothing here asks for) need toppra's own (COMPILED_PASSES False)."""

    def __init__(self, constraints: list[Any], path: Any, gridpoints: np.ndarray, kernels: Any) -> None:
        grid = np.array(gridpoints)
        self.deltas = grid[1:] - grid[:-1]
        self.params = [c.compute_constraint_params(path, grid) for c in constraints]
        self.rows = kernels.stage_rows(self.params, len(self.deltas))
        self.warm = np.zeros(4, dtype=np.int64)
        self.kernels = kernels

    def get_no_stages(self) -> int:
        return len(self.deltas)

    def get_no_vars(self) -> int:
        return 2

    def get_deltas(self) -> np.ndarray:
        return self.deltas

    def controllable_sets(self, sd_min: float, sd_max: float) -> np.ndarray:
        """The lean `compute_controllable_sets`, compiled."""
        out = np.empty((len(self.deltas) + 1, 2))
        self.kernels.controllable_sets(sd_min, sd_max, *self.rows, self.deltas, self.warm, out)
        return out

    def forward(self, x_start: float, sets: np.ndarray, tiny: float, max_tries: int) -> tuple[np.ndarray, np.ndarray]:
        """The lean forward pass, compiled: (x at every grid point, u of every stage)."""
        n = len(self.deltas)
        xs, us = np.empty(n + 1), np.empty(n)
        self.kernels.forward_pass(x_start, sets, *self.rows, self.deltas, self.warm, tiny, max_tries, xs, us)
        return xs, us


def _compiled_passes(constraints: list[Any], canonical_linear: Any) -> Any:
    """The passes' kernels when this plan may take them (COMPILED_PASSES, numba there, every constraint canonical
    linear and the same at every grid point, as toppra's seidel wrapper requires), else None."""
    if not (COMPILED_PASSES and compiled.ON):
        return None
    if any(c.get_constraint_type() != canonical_linear or not c.identical for c in constraints):
        return None
    return compiled.kernels("orc_rpl.motion.toppra_kernels")


def lean_toppra(toppra: Any) -> type:
    """toppra's TOPPRA class with the lean passes (toppra: the imported package)."""
    from_constants = toppra.constants
    tiny, small, max_tries = from_constants.TINY, from_constants.SMALL, from_constants.MAX_TRIES
    codes = toppra.algorithm.algorithm.ParameterizationReturnCode
    base_init = toppra.algorithm.algorithm.ParameterizationAlgorithm.__init__
    canonical_linear = toppra.constraint.ConstraintType.CanonicalLinear
    nan = math.nan

    class LeanTOPPRA(toppra.algorithm.TOPPRA):  # type: ignore[misc, name-defined]
        """TOPPRA with `compute_controllable_sets` and `compute_parameterization` as toppra's, leaner (compiled,
        on a CompiledSeidel, where `_compiled_passes` allows: then toppra's seidel wrapper is not made)."""

        def __init__(self, constraint_list: list[Any], path: Any, gridpoints: Any = None, solver_wrapper: Any = None,
                     parametrizer: Any = None, **kwargs: Any) -> None:
            kernels = _compiled_passes(constraint_list, canonical_linear)
            if kernels is None or gridpoints is None or solver_wrapper != "seidel":
                super().__init__(constraint_list, path, gridpoints=gridpoints, solver_wrapper=solver_wrapper,
                                 parametrizer=parametrizer, **kwargs)
                return
            base_init(self, constraint_list, path, gridpoints=gridpoints, parametrizer=parametrizer, **kwargs)
            self.solver_wrapper = CompiledSeidel(self.constraints, self.path, self.gridpoints, kernels)

        def compute_controllable_sets(self, sdmin: float, sdmax: float) -> np.ndarray:
            assert sdmin <= sdmax and 0 <= sdmin
            if isinstance(self.solver_wrapper, CompiledSeidel):
                return self.solver_wrapper.controllable_sets(sdmin, sdmax)
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
            if isinstance(wrapper, CompiledSeidel):
                xs_vec, sdd_vec = wrapper.forward(x_start, K, tiny, max_tries)
                return self._result(np.sqrt(xs_vec), sdd_vec, K, return_data, wrapper)
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
            return self._result(np.sqrt(np.array(xs, dtype=float)), np.array(us, dtype=float), K, return_data,
                                wrapper)

        def _result(self, sd_vec: np.ndarray, sdd_vec: np.ndarray, K: np.ndarray, return_data: bool,
                    wrapper: Any) -> tuple:
            """toppra's ending of compute_parameterization: the problem data and the return tuple."""
            v_vec = np.zeros((len(sdd_vec), wrapper.get_no_vars() - 2))
            self._problem_data.sd_vec = sd_vec
            self._problem_data.sdd_vec = sdd_vec
            self._problem_data.return_code = codes.ErrUnknown if np.isnan(sd_vec).any() else codes.Ok
            return (sdd_vec, sd_vec, v_vec, K) if return_data else (sdd_vec, sd_vec, v_vec)

    return LeanTOPPRA
