"""A casting's edge with bulges as a process model of the cell (deburring, thesis 2.1 and 4.5).

The edge is a polyline in the world (the grinder's nominal TCP path along it) with an outward unit normal
`n` (the direction the grinder retracts; the grinder presses along -n). Bulges sit on it: a raised cosine
of height h between the arc lengths s0 and s1 (m from the edge's first point); `profile` holds the material
above the nominal edge on a 0.5 mm grid.

The grinder sits on a compliant (active) flange with a stroke along -n: the robot's analog output
`AnaOut[stroke]` is the commanded stroke u (m, positive toward the part), the analog input `AnaIn[force]`
the measured normal force (N). Every call (each plant step, 1 ms, on the simulated cell):

    tip         = TCP - u n
    penetration = profile(s) - (tip - P(s)) . n     (s: the tip projected onto the edge)
    F           = k max(0, penetration)              (a stiff spring: k = 50 N/mm by default)
    dh/dt       = -K F v / w                         (Preston: v the tip's speed, w the wheel's width)

for the grid points within w/2 of the contact; the burr cannot be ground below the nominal edge (h >= 0:
the casting itself is not ground in this model). One pass at force F over a point removes K F whatever the
speed (dh/dt ~ F v over a contact time w / v); K = 1e-5 m/N: 0.3 mm a pass at 30 N. The contact force does
not act back on the arm (the stiff arm carries the flange; only the flange's stroke gives way).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

#: Grid of the profile along the edge (m).
GRID_M = 0.0005
#: The tip counts as at the edge within this distance sideways (across the edge and n) and this far beyond its ends.
SIDEWAYS_M = 0.01


@dataclass(frozen=True, slots=True)
class Bulge:
    """A bulge of the casting's edge: height `height_m` (its top) between arc lengths s0_m and s1_m."""

    s0_m: float
    s1_m: float
    height_m: float


class CastingEdge:
    """The edge as `CellIO.add_process`: reads the stroke output, writes the force input, grinds the bulges."""

    def __init__(self, edge: list[tuple[float, float, float]], bulges: list[Bulge], normal: tuple[float, float, float] = (0.0, 0.0, 1.0),
                 tcp: Callable[[], Any] | None = None, force_in: int = 8, stroke_out: int = 8,
                 stiffness_n_m: float = 5e4, removal_m_n: float = 1e-5, wheel_width_m: float = 0.01,
                 push: Callable[[np.ndarray, np.ndarray], None] | None = None) -> None:
        points = np.array(edge, dtype=float)
        if points.ndim != 2 or points.shape[1] != 3 or len(points) < 2:
            raise ValueError("an edge needs at least two points (x, y, z)")
        normal_v = np.array(normal, dtype=float)
        if np.linalg.norm(normal_v) < 1e-9:
            raise ValueError("the edge's normal must not be zero")
        self.points = points
        self.normal = normal_v / np.linalg.norm(normal_v)
        segments = np.diff(points, axis=0)
        lengths = np.linalg.norm(segments, axis=1)
        if np.any(lengths < 1e-9):
            raise ValueError("two consecutive points of the edge are the same")
        self._segments, self._lengths = segments, lengths
        self._starts = np.concatenate(([0.0], np.cumsum(lengths)))
        self.length_m = float(self._starts[-1])
        self.grid = np.arange(0.0, self.length_m + GRID_M / 2, GRID_M)
        self.profile = np.zeros_like(self.grid)
        self.bulges = list(bulges)
        for bulge in self.bulges:
            if not (0.0 <= bulge.s0_m < bulge.s1_m <= self.length_m) or bulge.height_m < 0:
                raise ValueError(f"a bulge needs 0 <= from < to <= {self.length_m * 1000:.1f} mm (the edge's length) "
                                 f"and a height >= 0; got {bulge}")
            inside = (self.grid >= bulge.s0_m) & (self.grid <= bulge.s1_m)
            phase = (self.grid[inside] - bulge.s0_m) / (bulge.s1_m - bulge.s0_m)
            self.profile[inside] = np.maximum(self.profile[inside], bulge.height_m * 0.5 * (1 - np.cos(2 * math.pi * phase)))
        self.initial_profile = self.profile.copy()
        self.tcp = tcp
        self.force_in, self.stroke_out = force_in, stroke_out
        self.stiffness_n_m, self.removal_m_n, self.wheel_width_m = stiffness_n_m, removal_m_n, wheel_width_m
        self.force_n = 0.0
        self.contact_s_m: float | None = None
        self._last: tuple[float, np.ndarray] | None = None
        self.push = push
        self._pushing = False

    # -- geometry --------------------------------------------------------------------------

    def project(self, point: np.ndarray) -> tuple[float, float, float]:
        """(arc length s, normal coordinate (point - P(s)) . n, sideways distance) of a point near the edge."""
        best: tuple[float, float, float] | None = None
        for i, (start, segment, length) in enumerate(zip(self.points, self._segments, self._lengths)):
            direction = segment / length
            along = float(np.clip(np.dot(point - start, direction), 0.0, length))
            offset = point - (start + along * direction)
            normal = float(np.dot(offset, self.normal))
            sideways = float(np.linalg.norm(offset - normal * self.normal))
            if best is None or sideways < best[2] - 1e-12:
                best = (float(self._starts[i]) + along, normal, sideways)
        assert best is not None
        return best

    def height_at(self, s_m: float) -> float:
        """The burr's height (m above the nominal edge) at arc length s."""
        return float(np.interp(s_m, self.grid, self.profile))

    def max_height_m(self, s0_m: float = 0.0, s1_m: float | None = None) -> float:
        """The highest remaining burr between s0 and s1 (the whole edge by default)."""
        s1 = self.length_m if s1_m is None else s1_m
        inside = (self.grid >= s0_m - 1e-12) & (self.grid <= s1 + 1e-12)
        return float(self.profile[inside].max()) if inside.any() else 0.0

    def remaining(self) -> list[tuple[Bulge, float]]:
        """Each configured bulge with the height left of it (m)."""
        return [(b, self.max_height_m(b.s0_m, b.s1_m)) for b in self.bulges]

    # -- process ---------------------------------------------------------------------------

    def __call__(self, io: Any, time_s: float) -> None:
        if self.tcp is None:
            return
        pose = self.tcp()
        stroke = float(io.bank("AnaOut")[self.stroke_out])
        tip = np.array((pose.x, pose.y, pose.z)) - stroke * self.normal
        s, normal, sideways = self.project(tip)
        force = 0.0
        self.contact_s_m = None
        if sideways <= SIDEWAYS_M:
            penetration = self.height_at(s) - normal
            if penetration > 0.0:
                force = self.stiffness_n_m * penetration
                self.contact_s_m = s
        if force > 0.0 and self._last is not None and time_s > self._last[0]:
            dt = time_s - self._last[0]
            speed = float(np.linalg.norm(tip - self._last[1])) / dt
            near = np.abs(self.grid - s) <= self.wheel_width_m / 2
            removal = self.removal_m_n * force * speed * dt / self.wheel_width_m
            self.profile[near] = np.maximum(0.0, self.profile[near] - removal)
        self._last = (time_s, tip)
        self.force_n = force
        if self.push is not None and (force > 0.0 or self._pushing):
            self.push(force * self.normal, tip)
            self._pushing = force > 0.0
        io.bank("AnaIn")[self.force_in] = force
