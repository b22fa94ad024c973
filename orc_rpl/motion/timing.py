"""Time-optimal path parameterisation with toppra (the one module that imports it) and its fallback profile."""

from __future__ import annotations

import functools
import logging
import math
from collections.abc import Callable
from dataclasses import dataclass
from importlib.metadata import version
from typing import Any

import numpy as np

from orc_rpl.errors import PlanningError
from orc_rpl.motion.gear_steps import GearSteps
from orc_rpl.motion.toppra_passes import lean_toppra
from orc_rpl.motion.trajectory import SplinePath, Trajectory, sample, segment_times

#: TOPP-RA's passes with their Python made lean (toppra_passes.py, the same numbers); False: toppra's own
#: (the reference; benchmarks/bench_motion_parts.py compares them)
LEAN_PASSES = True
LEAN_PASSES_OF = "0.6."  #: the toppra release whose passes toppra_passes.py rewrites (tests compare them)

#: grid density of the planner (rad of joint chord per grid interval) and its bounds
GRID_STEP_RAD = 0.03
GRID_MIN, GRID_MAX = 40, 150


@dataclass(frozen=True, slots=True)
class TimingLimits:
    """The limits one parameterisation respects."""

    qd_max: np.ndarray                    #: joint speed limits, rad/s
    qdd_max: np.ndarray                   #: joint acceleration limits, rad/s^2
    tau_max: np.ndarray | None = None     #: joint torque limits, N m (None: no torque constraint)
    inverse_dynamics: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray] | None = None
    tcp_jacobian: Callable[[np.ndarray], np.ndarray] | None = None   #: (3, n) linear Jacobian at q
    #: TCP speed limit (m/s, inf: none) for arrays of (owning motion id, its s)
    tcp_speed_m_s: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None
    #: joint speed override in (0, 1] for arrays of (owning motion id, its s)
    speed_fraction: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None
    load_kg: float = 0.0                  #: payload the torque model includes
    #: the same model for k states at once, f(q, qd, qdd, out) on (k, n) arrays (None: `inverse_dynamics` per state)
    inverse_dynamics_rows: Callable[[np.ndarray, np.ndarray, np.ndarray, np.ndarray], None] | None = None


@functools.cache
def _toppra() -> Any:
    """Import toppra on first use (it imports matplotlib) and build our two adapter classes."""
    import toppra
    import toppra.algorithm
    import toppra.constants
    import toppra.constraint
    import toppra.interpolator
    import toppra.solverwrapper

    logging.getLogger("toppra").setLevel(logging.ERROR)  # failures are reported by us, as PlanningError
    # Every TOPPRA() asks importlib whether optional solver packages are installed (a tenth of a
    # plan's time); the answer does not change while we run: ask once.
    solvers = toppra.solverwrapper.available_solvers(output_msg=False)
    toppra.solverwrapper.available_solvers = lambda output_msg=True: solvers
    discretization = toppra.constraint.DiscretizationType

    class AccelerationBound(toppra.constraint.JointAccelerationConstraint):
        """toppra's joint acceleration constraint, built without the printable summary its __init__
        formats with numpy's array printing (a fifth of a plan's time)."""

        def __init__(self, alim: np.ndarray) -> None:
            toppra.constraint.LinearConstraint.__init__(self)
            self.alim = np.array(alim, dtype=float)
            self.dof = self.alim.shape[0]
            self.set_discretization_type(discretization.Interpolation)
            self.identical = True
            self._format_string = "    Acceleration limit (alim)\n"

    class TorqueBound(toppra.constraint.JointTorqueConstraint):
        """toppra's joint torque constraint, likewise without the printable summary."""

        def __init__(self, inv_dyn: Callable[..., np.ndarray], tau_lim: np.ndarray, fs_coef: np.ndarray,
                     inv_dyn_rows: Callable[..., None] | None = None) -> None:
            toppra.constraint.LinearConstraint.__init__(self)
            self.inv_dyn = inv_dyn
            self.inv_dyn_rows = inv_dyn_rows
            self.tau_lim = np.array(tau_lim, dtype=float)
            self.fs_coef = np.array(fs_coef)
            self.dof = self.tau_lim.shape[0]
            self.set_discretization_type(discretization.Collocation)
            self.identical = True
            self._format_string = "    Torque limit (tau_lim)\n"

        def compute_constraint_params(self, path: Any, gridpoints: np.ndarray) -> tuple:
            """toppra's own (tau = a s'' + b s'^2 + c at each grid point), the model's torques at all grid
            points in three batched calls instead of three calls per point: the same numbers."""
            rows = self.inv_dyn_rows
            if rows is None or path.dof != self.get_dof():
                return super().compute_constraint_params(path, gridpoints)
            p, ps, pss = path.eval(gridpoints), path.evald(gridpoints), path.evaldd(gridpoints)
            dof = path.dof
            zero, a, b, c = np.zeros(p.shape), np.empty(p.shape), np.empty(p.shape), np.empty(p.shape)
            rows(p, zero, zero, c)
            rows(p, zero, ps, a)
            rows(p, ps, pss, b)
            a -= c
            b -= c
            c += self.fs_coef * np.sign(ps)   # dry friction, as toppra adds it
            eye = np.eye(dof)
            f, g = np.vstack([eye, -eye]), np.concatenate([self.tau_lim[:, 1], -self.tau_lim[:, 0]])
            return a, b, c, f, g, None, None

    class GeometricPath(toppra.interpolator.AbstractGeometricPath):
        """Our SplinePath seen as a toppra geometric path."""

        def __init__(self, path: SplinePath) -> None:
            self._p = path

        def __call__(self, ss: Any, order: int = 0) -> np.ndarray:
            return self._p(ss, order)

        @property
        def dof(self) -> int:
            return self._p.dof

        @property
        def path_interval(self) -> np.ndarray:
            return np.array([0.0, self._p.length])

    class SpeedBound(toppra.constraint.LinearConstraint):
        """Joint and TCP speed limits as a pure bound on x = sd^2 (toppra has no Cartesian velocity constraint)."""

        def __init__(self, xmax_at: Callable[[np.ndarray], np.ndarray], dof: int) -> None:
            super().__init__()
            self._xmax_at = xmax_at
            self.dof = dof
            self.identical = True

        def compute_constraint_params(self, path: Any, gridpoints: np.ndarray) -> tuple:
            xb = np.zeros((len(gridpoints), 2))
            xb[:, 1] = self._xmax_at(gridpoints)
            return None, None, None, None, None, None, xb

    # the lean passes are toppra 0.6's own, rewritten: another toppra keeps its own passes until they are compared
    lean = lean_toppra(toppra) if version("toppra").startswith(LEAN_PASSES_OF) else toppra.algorithm.TOPPRA
    return toppra, GeometricPath, SpeedBound, AccelerationBound, TorqueBound, lean


def preload() -> None:
    """Import toppra now (about 0.4 s with the matplotlib it pulls in) rather than inside the first move."""
    _toppra()


def xmax(path: SplinePath, grid: np.ndarray, limits: TimingLimits) -> np.ndarray:
    """Upper bound on sd^2 at each grid point from joint and TCP speed limits."""
    d1 = np.abs(path(grid, 1))
    owner, s = path.owner_and_s(grid)
    frac = limits.speed_fraction(owner, s) if limits.speed_fraction is not None else np.ones(len(grid))
    vmax = limits.qd_max[None, :] * frac[:, None]
    with np.errstate(divide="ignore"):
        out = np.min(np.where(d1 > 1e-12, (vmax / np.maximum(d1, 1e-12)) ** 2, np.inf), axis=1)
    if limits.tcp_speed_m_s is not None and limits.tcp_jacobian is not None:
        v = limits.tcp_speed_m_s(owner, s)
        q, d1s = path(grid), path(grid, 1)
        jacobian = limits.tcp_jacobian
        for i in np.flatnonzero(np.isfinite(v)):
            tcp_d1 = jacobian(q[i]) @ d1s[i]
            lin = math.sqrt(float(tcp_d1.dot(tcp_d1)))  # np.linalg.norm's own formula, without its checks
            if lin > 1e-12:
                out[i] = min(out[i], (v[i] / lin) ** 2)
    return np.minimum(out, 1e8)


def grid_for(path: SplinePath, points: int | None = None) -> np.ndarray:
    """Grid points along the path (uniform in x), dense enough for the collocation to hold between them."""
    n = points or int(min(GRID_MAX, max(GRID_MIN, math.ceil(path.length / GRID_STEP_RAD))))
    return np.linspace(0.0, path.length, n + 1)


def constraints(path: SplinePath, limits: TimingLimits) -> list[Any]:
    """toppra's constraints for timing `path` within `limits`: speeds (joint and TCP), accelerations, torques."""
    _, _, SpeedBound, AccelerationBound, TorqueBound, _ = _toppra()
    cons: list[Any] = [
        SpeedBound(lambda g: xmax(path, g, limits), path.dof),
        AccelerationBound(np.stack([-limits.qdd_max, limits.qdd_max], axis=1)),
    ]
    if limits.tau_max is not None and limits.inverse_dynamics is not None:
        cons.append(
            TorqueBound(limits.inverse_dynamics, np.stack([-limits.tau_max, limits.tau_max], axis=1), np.zeros(path.dof),
                        limits.inverse_dynamics_rows)
        )
    return cons


def toppra_profile(
    path: SplinePath, limits: TimingLimits, sd_start: float = 0.0, sd_end: float = 0.0, points: int | None = None,
    lean: bool | None = None,
) -> tuple[np.ndarray, np.ndarray] | None:
    """(grid, sd) of the time-optimal profile, or None when toppra finds none (never raises for toppra's sake);
    `lean` False: toppra's own passes (the reference of toppra_passes.py's); None: LEAN_PASSES."""
    toppra, GeometricPath, _, _, _, LeanTOPPRA = _toppra()
    grid = grid_for(path, points)
    cons = constraints(path, limits)
    try:
        # toppra's TOPPRA with its passes' Python made lean (toppra_passes.py: the same solves, the same numbers)
        algorithm = LeanTOPPRA if (LEAN_PASSES if lean is None else lean) else toppra.algorithm.TOPPRA
        algo = algorithm(cons, GeometricPath(path), gridpoints=grid, solver_wrapper="seidel")
        result = algo.compute_parameterization(sd_start, sd_end, return_data=True)
        data = algo.problem_data
        if data.return_code != toppra.algorithm.algorithm.ParameterizationReturnCode.Ok:
            k = result[3] if len(result) > 3 else None
            # A replan from a moving state can sit a hair above the controllable set: retry at its edge.
            if k is not None and np.all(np.isfinite(k)) and sd_start > 0 and sd_start**2 > k[0, 1] >= 0.95 * sd_start**2:
                algo.compute_parameterization(math.sqrt(k[0, 1]), sd_end)
                data = algo.problem_data
            if data.return_code != toppra.algorithm.algorithm.ParameterizationReturnCode.Ok:
                return None
        sd = np.asarray(data.sd_vec, dtype=float).reshape(-1)
    except (ValueError, ArithmeticError, AssertionError, IndexError):
        return None
    if not np.all(np.isfinite(sd)) or np.any(sd < -1e-9):
        return None
    return np.asarray(data.gridpoints, dtype=float).reshape(-1), np.maximum(sd, 0.0)


def fallback_profile(path: SplinePath, limits: TimingLimits, sd_start: float, sd_end: float) -> tuple[np.ndarray, np.ndarray]:
    """A conservative profile without toppra: speed bounds, half the acceleration limits, forward/backward passes."""
    grid = grid_for(path, GRID_MAX)
    x_cap = xmax(path, grid, limits)
    d1 = np.maximum(np.abs(path(grid, 1)), 1e-9)
    d2 = np.abs(path(grid, 2))
    # path acceleration bound ignoring the curvature term, then keep the curvature term under half the limit
    u_max = 0.5 * np.min(limits.qdd_max[None, :] / d1, axis=1)
    x_cap = np.minimum(x_cap, np.min(0.5 * limits.qdd_max[None, :] / np.maximum(d2, 1e-9), axis=1))
    dx = np.diff(grid)
    x = np.minimum(x_cap, np.inf)
    x[0] = min(x_cap[0], sd_start**2)
    for i in range(len(dx)):
        x[i + 1] = min(x[i + 1], x[i] + 2.0 * u_max[i] * dx[i])
    x[-1] = min(x[-1], sd_end**2)
    for i in range(len(dx) - 1, -1, -1):
        x[i] = min(x[i], x[i + 1] + 2.0 * u_max[i] * dx[i])
    return grid, np.sqrt(np.maximum(x, 0.0))


def parameterize(
    path: SplinePath,
    limits: TimingLimits,
    dt_s: float,
    sub: int = 4,
    sd_start: float = 0.0,
    sd_end: float = 0.0,
    min_duration_s: float | None = None,
    points: int | None = None,
    smoothing_s: tuple[float, ...] = (),
    gear_steps: GearSteps | None = None,
) -> tuple[Trajectory, bool]:
    """The trajectory along `path` at the motion-cycle period, and whether toppra (not the fallback) timed it;
    `smoothing_s`: a trajectory from rest has its time scaling averaged over these windows (trajectory.smoothed),
    with `gear_steps` over as much of them as its steps' twist of the elastic gears calls for (motion/gear_steps.py)."""
    prof = toppra_profile(path, limits, sd_start, sd_end, points)
    optimal = prof is not None
    if prof is None:
        prof = fallback_profile(path, limits, sd_start, sd_end)
        if prof[1][0] < sd_start - 1e-6:
            raise PlanningError(
                "the path cannot be timed from the current speed within the limits (toppra failed and so did the fallback)"
            )
    grid, sd = prof
    if min_duration_s and sd_start == 0.0:
        total = float(np.sum(segment_times(grid, sd)))
        if total < min_duration_s:
            sd = sd * (total / min_duration_s)  # uniform time scaling keeps every limit (the torque box is convex)
    averaged_over_s = None
    if smoothing_s and gear_steps is not None and sd_start == 0.0 and limits.inverse_dynamics is not None:
        averaged_over_s = gear_steps.windows(smoothing_s,
                                             gear_steps.largest_twist_rad(path, grid, sd, limits.inverse_dynamics))
    return sample(path, grid, sd, dt_s, sub, smoothing_s, averaged_over_s), optimal
