"""Helpers for the motion tests: poses near the TCP and distances to targets."""

from __future__ import annotations

import numpy as np

from orc_rpl.motion import MotionLayer
from orc_rpl.world.pose import Pose


def pose_here(layer: MotionLayer, dx: float = 0.0, dy: float = 0.0, dz: float = 0.0) -> Pose:
    """The TCP pose now, displaced in world axes (orientation kept)."""
    p = Pose.from_matrix(layer.tcp_pose())
    return Pose(p.x + dx, p.y + dy, p.z + dz, p.a, p.b, p.c)


def tcp_error(layer: MotionLayer, target: Pose) -> tuple[float, float]:
    """Position (mm) and orientation (deg) distance of the measured TCP from a target pose."""
    t = layer.tcp_pose()
    g = target.matrix()
    pos = float(np.linalg.norm(t[:3, 3] - g[:3, 3])) * 1000.0
    cos = (np.trace(g[:3, :3].T @ t[:3, :3]) - 1.0) / 2.0
    return pos, float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))
