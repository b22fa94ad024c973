"""Where a camera stands to frame the work: the robot's reach and every point the program or the world names."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: Seen from the front left and from above, as a person standing beside the cell would.
AZIMUTH_DEG = 225.0
ELEVATION_DEG = -25.0


@dataclass(frozen=True, slots=True)
class Framing:
    """A camera aimed at `lookat_m` from `distance_m`, turned `azimuth_deg` about z, `elevation_deg` up (negative: from above)."""

    lookat_m: tuple[float, float, float]
    distance_m: float
    azimuth_deg: float = AZIMUTH_DEG
    elevation_deg: float = ELEVATION_DEG

    def camera_position_m(self) -> tuple[float, float, float]:
        """The camera's position (MuJoCo's free-camera convention: it looks along azimuth and elevation)."""
        az, el = math.radians(self.azimuth_deg), math.radians(self.elevation_deg)
        forward = np.array([math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)])
        x, y, z = np.asarray(self.lookat_m) - self.distance_m * forward
        return (float(x), float(y), float(z))


def frame_work(points_m: np.ndarray, fov_deg: float = 45.0) -> Framing:
    """A framing that keeps every point (the robot's base and flange, positions, objects; (N, 3) in m) in view."""
    points = np.asarray(points_m, dtype=float).reshape(-1, 3)
    low, high = points.min(axis=0), points.max(axis=0)
    centre = (low + high) / 2
    radius = max(0.8, float(np.linalg.norm(high - low)) / 2)
    # the sphere around the work fills the picture's height with a margin
    distance = 1.25 * radius / math.sin(math.radians(fov_deg) / 2)
    return Framing((float(centre[0]), float(centre[1]), float(centre[2])), distance)
