"""A ragged weld seam as a process model (thesis 2.3): what a simulated LaserDistance sensor sees.

The seam runs along a straight line from `start` to `end` (world, m) — by default the first path the laser is
used along (RecordSeam's path, or the TRACKMOVE) — and wanders sideways by a lateral offset profile:

    offset(u) = amplitude * sin(2 pi u / wavelength) + raggedness noise(u)

u is the distance along the line; the noise is white noise from a fixed `seed`, low-passed over
`correlation` and scaled to the standard deviation `raggedness`. The lateral direction is horizontal and
perpendicular to the line (world z x line direction). The seam starts at `edge` (its start edge, seen by
`EdgeDetected` within `edge_width`) and runs to `end` + 1 m; over `missing` = [from, to] (distances along
the line) there is no seam (the laser loses it: TRACKMOVE raises SeamLost). The laser beam is at the TCP and
sees a seam within `range` sideways; each sample is recorded in `trace` as (u, TCP lateral position, seam
offset), from which the tracking error against the true seam is measured. `noise` adds white measurement noise of that
standard deviation to each reading (a noisy laser; seeded from `seed`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

#: Defaults (m): a gently curved seam with raggedness of a few tenths of a millimetre.
DEFAULTS = {"amplitude": 0.004, "wavelength": 0.4, "raggedness": 0.0003, "correlation": 0.004, "edge": 0.02,
            "edge_width": 0.002, "range": 0.015, "seed": 2}
GRID_M = 0.0005           #: resolution of the noise profile
TAIL_M = 1.0              #: the seam goes on this far past `end` (a calibration piece is short)


@dataclass(frozen=True, slots=True)
class SeamSample:
    u_m: float              #: distance along the seam line
    tcp_lateral_m: float    #: the TCP's lateral position (from the line)
    seam_offset_m: float    #: the seam's true lateral offset there

    @property
    def error_m(self) -> float:
        return self.seam_offset_m - self.tcp_lateral_m


class SeamProcess:
    """The ragged seam of the cell; `measure(p)` is the simulated laser at TCP position p (world, m)."""

    def __init__(self, start: tuple[float, float, float] | None = None, end: tuple[float, float, float] | None = None,
                 amplitude: float = DEFAULTS["amplitude"], wavelength: float = DEFAULTS["wavelength"],
                 raggedness: float = DEFAULTS["raggedness"], correlation: float = DEFAULTS["correlation"],
                 edge: float = DEFAULTS["edge"], edge_width: float = DEFAULTS["edge_width"],
                 range: float = DEFAULTS["range"], seed: int = int(DEFAULTS["seed"]),  # noqa: A002 - the yaml key
                 missing: tuple[float, float] | None = None, noise: float = 0.0) -> None:
        if noise < 0:
            raise ValueError("seam: the laser's noise must be >= 0")
        self.noise = noise      #: the laser's measurement noise (m, standard deviation of each reading; seeded)
        self._rng = np.random.default_rng(seed + 1)
        if wavelength <= 0 or raggedness < 0 or correlation <= 0 or range <= 0 or edge_width <= 0:
            raise ValueError("seam: wavelength, correlation, range and edge_width must be > 0, raggedness >= 0")
        self.amplitude, self.wavelength, self.raggedness, self.correlation = amplitude, wavelength, raggedness, correlation
        self.edge, self.edge_width, self.range, self.seed = edge, edge_width, range, seed
        self.missing = missing
        self.trace: list[SeamSample] = []
        self._start = self._dir = self._lateral = None
        self.length_m = 0.0
        self._noise = np.zeros(1)
        if start is not None and end is not None:
            self.anchor(start, end)

    @property
    def anchored(self) -> bool:
        return self._start is not None

    def anchor(self, start: Any, end: Any) -> None:
        """Lay the seam along the line start -> end (world, m)."""
        a, b = np.asarray(start, float)[:3], np.asarray(end, float)[:3]
        d = b - a
        length = float(np.linalg.norm(d))
        if length < 1e-6:
            raise ValueError("seam: start and end are the same point")
        d /= length
        lateral = np.cross((0.0, 0.0, 1.0), d)
        if np.linalg.norm(lateral) < 1e-6:
            lateral = np.array((1.0, 0.0, 0.0))
        self._start, self._dir, self._lateral = a, d, lateral / np.linalg.norm(lateral)
        self.length_m = length
        n = int((length + TAIL_M) / GRID_M) + 2
        white = np.random.default_rng(self.seed).standard_normal(n + 200)
        k = max(1, int(round(self.correlation / GRID_M)))
        kernel = np.exp(-0.5 * (np.arange(-3 * k, 3 * k + 1) / k) ** 2)
        smooth = np.convolve(white, kernel, mode="same")[100:100 + n]
        std = float(np.std(smooth))
        self._noise = smooth * (self.raggedness / std if std > 0 else 0.0)

    def offset_m(self, u: float) -> float:
        """The seam's true lateral offset at distance u along the line."""
        i = min(max(u / GRID_M, 0.0), len(self._noise) - 1.001)
        j = int(i)
        noise = self._noise[j] + (i - j) * (self._noise[j + 1] - self._noise[j]) if len(self._noise) > 1 else 0.0
        return self.amplitude * math.sin(2 * math.pi * u / self.wavelength) + float(noise)

    def point(self, u: float) -> tuple[float, float, float]:
        """The seam's world position at distance u along the line."""
        p = self._start + u * self._dir + self.offset_m(u) * self._lateral
        return (float(p[0]), float(p[1]), float(p[2]))

    def along(self, p: Any) -> tuple[float, float]:
        """(u, lateral) of a world point relative to the seam line."""
        r = np.asarray(p, float)[:3] - self._start
        return float(r @ self._dir), float(r @ self._lateral)

    def lateral_direction(self) -> tuple[float, float, float]:
        return tuple(float(v) for v in self._lateral)  # type: ignore[return-value]

    def present(self, u: float) -> bool:
        if u < self.edge or u > self.length_m + TAIL_M:
            return False
        return not (self.missing is not None and self.missing[0] <= u <= self.missing[1])

    def measure(self, p: Any) -> tuple[bool, float, bool]:
        """The laser at TCP position p: (seam found, the seam's lateral offset from the beam in m, edge under it)."""
        if self._start is None:
            return False, math.nan, False
        u, lateral = self.along(p)
        seam = self.offset_m(u)
        rel = seam - lateral
        in_range = abs(rel) <= self.range
        edge = abs(u - self.edge) <= self.edge_width and abs(self.offset_m(self.edge) - lateral) <= self.range
        found = in_range and self.present(u)
        if found:
            self.trace.append(SeamSample(u, lateral, seam))
            if self.noise > 0:
                rel += float(self._rng.normal(0.0, self.noise))
        return found, rel if found else math.nan, edge

    def __call__(self, io: Any, time_s: float) -> None:
        """As a process of the cell's IO (so the sensors find it): nothing to do per plant step."""


def cell_seam(io: Any) -> SeamProcess:
    """The cell's SeamProcess (from a script's `seam:`), or a default one added to the cell's IO now."""
    seam = next((p for p in getattr(io, "processes", ()) if isinstance(p, SeamProcess)), None)
    if seam is None:
        seam = SeamProcess()
        io.add_process(seam)
    return seam
