"""The motion layer's external axes: moves that carry axis targets, and coordinated motion relative to a moving frame.

A move's external axes go from where they are to their targets linearly in the move's path coordinate s,
so they start and arrive with the arm. Every motion cycle the axes are handed the same path state as the
arm (arm/external.py's stages), and their references go to the backend's drives (`drive_axes`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.spatial.transform import Rotation, Slerp

from orc_rpl.arm.external import AxisLimits, ExternalAxisStage
from orc_rpl.errors import UsageError
from orc_rpl.motion.specs import FunctionMotion, Motion, MoveStatus, Params
from orc_rpl.world.pose import Pose
from orc_rpl.world.world import World

#: Margin on an axis' shortest time (speed and acceleration limits) when it sets a move's least duration.
TIME_MARGIN = 1.15


def solo_time_s(distance: float, limits: AxisLimits) -> float:
    """The duration of a cosine profile over `distance` within a speed and an acceleration limit."""
    d = abs(distance)
    return max(math.pi * d / (2.0 * limits.speed_si), math.pi * math.sqrt(d / (2.0 * limits.acceleration_si)))


def shortest_time_s(distance: float, limits: AxisLimits) -> float:
    """The shortest time a move of `distance` takes within a speed and an acceleration limit (trapezoid)."""
    d, v, a = abs(distance), limits.speed_si, limits.acceleration_si
    if d <= v * v / a:
        return 2.0 * math.sqrt(d / a)
    return d / v + v / a


class ExternalAxes:
    """The cell's external axes as the motion layer drives them (values in m or rad)."""

    def __init__(self, limits: Mapping[str, AxisLimits], home: Mapping[str, float]) -> None:
        self.limits = dict(limits)
        self.planned = dict(home)                       #: where the axes are when every accepted move is done
        self.moves: dict[int, tuple[dict[str, float], dict[str, float]]] = {}   #: move id -> (from, to)
        self._last: tuple[float, float] | None = None   #: path state at the last cycle's end (x, s')
        #: a move of the axes alone while the arm stands (a jog, a positioner turned under a still TCP):
        #: (handle, start values, end values, elapsed s, duration s), timed by the axes' own limits
        self.solo: tuple[Any, dict[str, float], dict[str, float], float, float] | None = None

    def request(self, layer: Any, motion: Motion, params: Params, targets: Mapping[str, float],
                actions: Any = None) -> Any:
        """A move of the arm with axis targets, in one path coordinate; returns the MoveHandle."""
        for name in targets:
            if name not in self.limits:
                raise UsageError(f"no external axis '{name}' in this cell" + (f" (it has {', '.join(self.limits)})" if self.limits else ""))
        start = dict(self.planned)
        end = {**start, **{k: float(v) for k, v in targets.items()}}
        least = max((shortest_time_s(end[k] - start[k], self.limits[k]) * TIME_MARGIN for k in targets), default=0.0)
        if least > (params.time_s or 0.0):
            params = dataclasses.replace(params, time_s=least)
        self.moves[layer._next_id] = (start, end)  # known before the move can start (move() may start it at once)
        handle = layer.move(motion, params, actions)
        if handle.done:
            self.moves.pop(handle.id, None)
            if handle.status is MoveStatus.READY and end != start:  # the arm has nowhere to go: the axes move alone
                handle.done, handle.status = False, MoveStatus.SPAWNED
                self.move_alone(handle, end)
        else:
            self.planned = end
        return handle

    def move_alone(self, handle: Any, targets: Mapping[str, float]) -> None:
        """Move axes while the arm stands still (from where they will be); `handle` is done when they arrive."""
        start = dict(self.planned)
        end = {**start, **{k: float(v) for k, v in targets.items()}}
        duration = max((solo_time_s(end[k] - start[k], self.limits[k]) for k in end), default=0.0)
        self.solo = (handle, start, end, 0.0, max(duration, 1e-9))  # handle None: nobody waits (a jog)
        self.planned = end

    # -- in the motion cycle -----------------------------------------------------------

    def stages(self, traj: Any, handles: list[Any]) -> list[ExternalAxisStage]:
        """A stage per axis that moves in this trajectory (none when no move of it carries axis targets)."""
        if not any(h.id in self.moves for h in handles):
            return []
        return [ExternalAxisStage(name, self._profile(traj, name), self.limits[name]) for name in self.limits]

    def _profile(self, traj: Any, name: str) -> Any:
        """The axis' value along the path parameter x and its derivatives by x: a cubic spline through its values at
        the path's knots, interpolated as the arm's joint path is (SplinePath), so that between the knots the axis and
        the arm stay on one path and e'' is the spline's, continuous (a difference quotient of the values, linear in s
        between the knots, was a spike wherever its stencil held a knot: a stage's range of s'' far off for a cycle,
        and the arm's references with it)."""
        knots = np.asarray(traj.path.x_knots, dtype=float)
        x_first, x_last = float(knots[0]), float(knots[-1])
        made: list[CubicSpline] = []

        def spline() -> CubicSpline:
            # made at the first call, from the moves as they are then (a move's axis targets are known by then; the
            # others' value is the axes' planned one, as the request has it once the move is made)
            if not made:
                owners, ss = traj.path.owner_and_s(knots)
                values = np.empty(len(knots))
                for i, (owner, s) in enumerate(zip(owners.tolist(), ss.tolist())):
                    start_end = self.moves.get(int(owner))
                    values[i] = self.planned[name] if start_end is None else (
                        start_end[0][name] + (start_end[1][name] - start_end[0][name]) * s)
                made.append(CubicSpline(knots, values, bc_type="not-a-knot" if len(knots) > 2 else ((2, 0.0), (2, 0.0))))
            return made[0]

        def profile(x: float, order: int) -> float:
            return float(spline()(min(max(x, x_first), x_last), order))

        return profile

    def cycle(self, backend: Any, stages: list[ExternalAxisStage], x: float | None, sd: float, period_s: float) -> None:
        """Hand the path state at the end of this cycle (x, s') to every stage; their references to the drives."""
        drive = getattr(backend, "drive_axes", None)
        if drive is None:
            return
        if x is None or not stages:
            self._last = None
            if x is None and self.solo is not None:
                drive(self._solo_step(period_s), period_s)
                return
            drive({}, period_s)
            return
        sdd = 0.0 if self._last is None else (sd - self._last[1]) / period_s
        self._last = (x, sd)
        drive({s.name: s.reference(x, sd, sdd) for s in stages}, period_s)

    def _solo_step(self, period_s: float) -> dict[str, tuple[float, float, float]]:
        """The references of a move of the axes alone at the end of this cycle: a cosine profile in time."""
        assert self.solo is not None
        handle, start, end, elapsed, duration = self.solo
        t = min(elapsed + period_s, duration)
        w = math.pi / duration
        out = {}
        for name in end:
            d = end[name] - start[name]
            out[name] = (start[name] + 0.5 * d * (1.0 - math.cos(w * t)), 0.5 * d * w * math.sin(w * t),
                         0.5 * d * w * w * math.cos(w * t))
        if t >= duration:
            self.solo = None
            if handle is not None:
                handle.done, handle.status = True, MoveStatus.READY
        else:
            self.solo = (handle, start, end, t, duration)
        return out

    def finished(self, move_id: int) -> None:
        """A move is done: forget its axis profile."""
        self.moves.pop(move_id, None)


def external_axes_of(world: World) -> ExternalAxes | None:
    """The external axes (tracks, positioners) a world declares, at their homes; None when it has none."""
    names = [n for n in world.moving_frames() if world.object(n).axis.joint != "conveyor"]  # type: ignore[union-attr]
    if not names:
        return None
    axes = {n: world.object(n).axis for n in names}
    limits = {n: AxisLimits(a.speed_si, a.acceleration_si) for n, a in axes.items()}  # type: ignore[union-attr]
    return ExternalAxes(limits, {n: a.home_si for n, a in axes.items()})  # type: ignore[union-attr]


def world_frame_in_base(world: World, frame: str) -> Callable[[Mapping[str, float]], np.ndarray]:
    """A frame of the world (on a moving frame) in the robot's base frame, for given axis values."""
    return lambda values: world.with_axes(values).relative_pose(frame, "robot").matrix()


def coordinated_motion(frame_in_base: Callable[[Mapping[str, float]], np.ndarray], start: np.ndarray, target: np.ndarray,
                       axes_from: Mapping[str, float], axes_to: Mapping[str, float],
                       tool: np.ndarray | None = None) -> FunctionMotion:
    """A straight TCP path relative to a frame on a moving frame while the axes move (coordinated motion).

    `start` and `target` are 4x4 TCP poses in that frame, `frame_in_base(values)` the frame in the robot's base
    frame (which a track may carry) when the axes are at `values`: at path coordinate s the base, the frame
    and the TCP are where the axes are at s.
    """
    slerp = Slerp([0.0, 1.0], Rotation.from_matrix(np.stack([start[:3, :3], target[:3, :3]])))
    cache: dict[float, Pose] = {}

    def pose(s: float) -> Pose:
        found = cache.get(s)
        if found is None:
            values = {k: axes_from[k] + (axes_to[k] - axes_from[k]) * s for k in axes_to}
            rel = np.eye(4)
            rel[:3, :3] = slerp([s]).as_matrix()[0]
            rel[:3, 3] = start[:3, 3] + (target[:3, 3] - start[:3, 3]) * s
            in_base = frame_in_base(values) @ rel
            found = cache[s] = Pose.from_matrix(in_base)
        return found

    return FunctionMotion(*(lambda s, k=k: float(getattr(pose(s), k)) for k in "xyzabc"), tool=tool)  # type: ignore[misc]
