"""Joint splines over dense paths and trajectories sampled at the motion-cycle period from a path-velocity profile."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.interpolate import CubicSpline

from orc_rpl.errors import PlanningError
from orc_rpl.motion.paths import DensePath
from orc_rpl.plant import compiled


#: grids up to this many points have their spline values kept (toppra's; not the servo-rate samples)
GRID_CACHE_MAX = 512


_loaded_kernels: list[Any] = []


def _spline_kernels() -> Any:
    """The spline kernel's module (motion/spline_kernels.py), imported when first needed; None where the kernels are off."""
    if not _loaded_kernels:
        _loaded_kernels.append(compiled.kernels("orc_rpl.motion.spline_kernels"))
    return _loaded_kernels[0]


class SplinePath:
    """A C2 joint path q(x) through a dense path's samples, x being the joint-space chord length (rad)."""

    def __init__(self, dense: DensePath) -> None:
        steps = np.linalg.norm(np.diff(dense.q, axis=0), axis=1)
        keep = np.concatenate([[True], steps > 1e-10])  # repeated samples would stall the chord parameter
        self.dense = DensePath(dense.q[keep], dense.tcp[keep], dense.owner[keep], dense.s[keep])
        q = self.dense.q
        if len(q) < 2:
            raise PlanningError("the path has no length")
        self.x_knots = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(q, axis=0), axis=1))])
        self.length = float(self.x_knots[-1])
        if len(q) == 2:  # a two-point spline is the straight line it should be
            self.spline = CubicSpline(self.x_knots, q, bc_type=((2, np.zeros(q.shape[1])), (2, np.zeros(q.shape[1]))))
        else:
            self.spline = CubicSpline(self.x_knots, q, bc_type="not-a-knot")
        self.dof = q.shape[1]
        # the spline's breakpoints and coefficients as the compiled evaluation reads them (scipy's properties
        # check them at every access)
        self._breaks, self._coefficients = np.ascontiguousarray(self.spline.x), np.ascontiguousarray(self.spline.c)
        # toppra's constraints and our speed bound evaluate the same grid eight times per timing:
        # keep the last grid's values (by content) and hand out copies
        self._grid_key: bytes | None = None
        self._on_grid: dict[int, np.ndarray] = {}

    def __call__(self, x: np.ndarray | float, order: int = 0) -> np.ndarray:
        if not isinstance(x, np.ndarray) or x.ndim != 1 or x.dtype != np.float64 or len(x) > GRID_CACHE_MAX:
            return self.spline(x, order)
        key = x.tobytes()
        if key != self._grid_key:
            self._grid_key, self._on_grid = key, {}
        values = self._on_grid.get(order)
        if values is None:
            values = self._on_grid[order] = self.spline(x, order)
        return values.copy()

    def orders(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The path and its first two derivatives at the points x (1-D, float), at once: `self(x, order)`'s
        numbers (compiled where the kernels are on: the motion cycle of a time-scaled trajectory calls this)."""
        kernels = _spline_kernels()
        if compiled.ON and kernels is not None:
            out = kernels.spline_orders(self._breaks, self._coefficients, x)
            return out[0], out[1], out[2]
        spline = self.spline
        return spline(x, 0), spline(x, 1), spline(x, 2)

    def owner_and_s(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The owning motion id and its path coordinate s at path parameters x."""
        k = self.x_knots
        i = np.clip(np.searchsorted(k, x, side="right") - 1, 0, len(k) - 2)
        frac = np.clip((x - k[i]) / np.maximum(k[i + 1] - k[i], 1e-15), 0.0, 1.0)
        own, s = self.dense.owner, self.dense.s
        same = own[i] == own[i + 1]
        s_x = np.where(same, s[i] + frac * (s[i + 1] - s[i]), s[i])
        return own[i], s_x

    def owner_and_s_at(self, x: float) -> tuple[int, float]:
        """`owner_and_s` at one path parameter, in Python numbers (the motion cycle of a time-scaled trajectory
        asks every cycle): the same operations on the same numbers."""
        k = self.x_knots
        i = min(max(int(k.searchsorted(x, side="right")) - 1, 0), len(k) - 2)
        k0, k1 = k.item(i), k.item(i + 1)
        frac = min(max((x - k0) / max(k1 - k0, 1e-15), 0.0), 1.0)
        own, s = self.dense.owner, self.dense.s
        owner, s0 = int(own.item(i)), s.item(i)
        return owner, (s0 + frac * (s.item(i + 1) - s0) if owner == own.item(i + 1) else s0)

    def x_of_index(self, idx: int) -> float:
        """The parameter x of dense sample idx."""
        return float(self.x_knots[idx])


@dataclass(slots=True)
class Trajectory:
    """References at every servo step (the `_f` arrays), grouped in motion cycles of `sub` steps.

    Sample 0 is the state the trajectory starts from (already commanded); motion cycle k
    (1..cycles) commands fine rows (k-1)*sub+1 .. k*sub.
    """

    dt_s: float               #: motion-cycle period
    sub: int                  #: servo steps per motion cycle
    path: SplinePath
    x_f: np.ndarray           #: path parameter per servo step
    sd_f: np.ndarray          #: path velocity per servo step
    q_f: np.ndarray           #: (cycles*sub+1, n)
    qd_f: np.ndarray
    qdd_f: np.ndarray
    owner: np.ndarray         #: (cycles+1,) motion id per motion-cycle sample
    s: np.ndarray             #: (cycles+1,) that motion's s per motion-cycle sample
    exact_duration_s: float   #: the profile's duration before rounding up to whole cycles
    blendable: bool = True    #: a zone motion may replan from inside it
    kind: str = "path"        #: "path" (timed along path), "short" (ruckig), "timed" (function of t), "brake"
    smoothing_s: tuple[float, ...] = ()   #: the layer's windows its time scaling was averaged for (`smoothed`), () none

    @property
    def cycles(self) -> int:
        return len(self.owner) - 1

    @property
    def duration_s(self) -> float:
        """Duration in whole motion cycles."""
        return self.cycles * self.dt_s

    @property
    def q(self) -> np.ndarray:
        return self.q_f[:: self.sub]

    @property
    def qd(self) -> np.ndarray:
        return self.qd_f[:: self.sub]

    @property
    def qdd(self) -> np.ndarray:
        return self.qdd_f[:: self.sub]

    @property
    def x(self) -> np.ndarray:
        return self.x_f[:: self.sub]

    def rows(self, k: int) -> slice:
        """The fine rows commanded in motion cycle k."""
        return slice((k - 1) * self.sub + 1, k * self.sub + 1)


def segment_times(x_grid: np.ndarray, sd_grid: np.ndarray) -> np.ndarray:
    """Durations of the constant-acceleration segments between grid points."""
    dx = np.diff(x_grid)
    vsum = sd_grid[:-1] + sd_grid[1:]
    if np.any(vsum <= 1e-12):
        raise PlanningError("the velocity profile stalls inside the path (limits leave no admissible speed)")
    return 2.0 * dx / vsum


def sample(path: SplinePath, x_grid: np.ndarray, sd_grid: np.ndarray, dt_s: float, sub: int,
           smoothing_s: tuple[float, ...] = (), averaged_over_s: tuple[float, ...] | None = None) -> Trajectory:
    """Sample a piecewise constant-acceleration profile (x_grid, sd_grid) at every servo step; with `smoothing_s`
    and a profile from rest, the `smoothed` trajectory (the path evaluated once, for the averaged time scaling),
    averaged over `averaged_over_s` when given (shorter windows for this trajectory: motion/gear_steps.py), the
    trajectory's `smoothing_s` being the layer's windows it was averaged for."""
    seg_t = segment_times(x_grid, sd_grid)
    t_grid = np.concatenate([[0.0], np.cumsum(seg_t)])
    total = float(t_grid[-1])
    cycles = max(1, math.ceil(total / dt_s - 1e-9))
    t = np.minimum(np.arange(cycles * sub + 1) * (dt_s / sub), total)
    i = np.clip(np.searchsorted(t_grid, t, side="right") - 1, 0, len(seg_t) - 1)
    acc = (sd_grid[1:] ** 2 - sd_grid[:-1] ** 2) / (2.0 * np.maximum(np.diff(x_grid), 1e-15))
    tau = t - t_grid[i]
    sd = np.maximum(sd_grid[i] + acc[i] * tau, 0.0)
    x = np.minimum(x_grid[i] + sd_grid[i] * tau + 0.5 * acc[i] * tau**2, x_grid[-1])
    sdd = acc[i].copy()
    ended = t >= total
    x[ended], sd[ended] = x_grid[-1], sd_grid[-1]
    if smoothing_s and sd[0] == 0.0:
        return _averaged(path, x, sd, dt_s, sub, smoothing_s if averaged_over_s is None else averaged_over_s, True,
                         "path", smoothing_s)
    if sd_grid[-1] == 0.0:
        sdd[ended] = 0.0
    return _evaluated(path, x, sd, sdd, dt_s, sub, total, True, "path", ())


def smoothed(traj: Trajectory, windows_s: tuple[float, ...]) -> Trajectory:
    """The trajectory on the same path with its time scaling x(t) averaged over each window in turn (FIR).

    A moving average of x(t) over T leaves the path f(x) as it is, starts and ends at rest where the
    original does, bounds the path acceleration by the original's and makes it continuous (two
    windows: its rate too), and lasts T longer; an average over the period of a resonance does not
    excite it (elastic gears: servo/two_mass.py). `sample(..., smoothing_s=windows_s)` gives the same
    trajectory without evaluating the path for the unaveraged one first (the planner's way).
    """
    return _averaged(traj.path, traj.x_f, traj.sd_f, traj.dt_s, traj.sub, windows_s, traj.blendable, traj.kind)


def _averaged(path: SplinePath, x: np.ndarray, sd: np.ndarray, dt_s: float, sub: int, windows_s: tuple[float, ...],
              blendable: bool, kind: str, averaged_for_s: tuple[float, ...] | None = None) -> Trajectory:
    """`smoothed`'s work on the servo-step samples of x(t) and its speed; `averaged_for_s`: the windows the trajectory
    records (the layer's, when these are shorter ones for this trajectory), None: these."""
    h = dt_s / sub
    sdd = np.append(np.diff(sd) / h, 0.0)
    x_end = x[-1]
    for window_s in windows_s:
        n = max(1, int(round(window_s / h)))
        box = np.full(n, 1.0 / n)
        pad = n - 1
        x = np.convolve(np.concatenate([np.full(pad, x[0]), x, np.full(pad, x[-1])]), box, "valid")
        sd = np.convolve(np.concatenate([np.zeros(pad), sd, np.zeros(pad)]), box, "valid")
        sdd = np.convolve(np.concatenate([np.zeros(pad), sdd, np.zeros(pad)]), box, "valid")
    # the averages of the end's samples are the end up to rounding: the path ends where it ends (s = 1 exactly,
    # as the moves that read it expect), never past it
    np.minimum(x, x_end, out=x)
    x[-1] = x_end
    rows = len(x)
    cycles = max(1, math.ceil((rows - 1) / sub))
    extra = cycles * sub + 1 - rows
    x = np.concatenate([x, np.full(extra, x[-1])])
    sd, sdd = np.concatenate([sd, np.zeros(extra)]), np.concatenate([sdd, np.zeros(extra)])
    return _evaluated(path, x, sd, sdd, dt_s, sub, (rows - 1) * h, blendable, kind,
                      tuple(windows_s if averaged_for_s is None else averaged_for_s))


def _evaluated(path: SplinePath, x: np.ndarray, sd: np.ndarray, sdd: np.ndarray, dt_s: float, sub: int, duration_s: float,
               blendable: bool, kind: str, smoothing_s: tuple[float, ...]) -> Trajectory:
    """The trajectory of the time scaling x(t), x', x'' at every servo step: the path and its derivatives there."""
    q, d1, d2 = path.orders(x)
    owner, s = path.owner_and_s(x[::sub])
    return Trajectory(dt_s, sub, path, x, sd, q, d1 * sd[:, None], d2 * (sd * sd)[:, None] + d1 * sdd[:, None],
                      owner, s, duration_s, blendable, kind, smoothing_s)
