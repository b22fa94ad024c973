"""Pose arithmetic shared by every layer: (x, y, z, a, b, c) with rotation Rz(a)·Ry(b)·Rx(c), lengths in m, angles in rad."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

WORLD = "world"


def rotation_zyx(a_rad: float, b_rad: float, c_rad: float) -> np.ndarray:
    """Rotation matrix Rz(a)·Ry(b)·Rx(c)."""
    ca, sa = math.cos(a_rad), math.sin(a_rad)
    cb, sb = math.cos(b_rad), math.sin(b_rad)
    cc, sc = math.cos(c_rad), math.sin(c_rad)
    return np.array(
        [
            [ca * cb, ca * sb * sc - sa * cc, ca * sb * cc + sa * sc],
            [sa * cb, sa * sb * sc + ca * cc, sa * sb * cc - ca * sc],
            [-sb, cb * sc, cb * cc],
        ]
    )


def zyx_angles(rotation: np.ndarray) -> tuple[float, float, float]:
    """The angles (a, b, c) with Rz(a)·Ry(b)·Rx(c) == rotation; at b = ±90° a takes all of the yaw."""
    r = rotation
    sb = -float(r[2, 0])
    sb = max(-1.0, min(1.0, sb))
    b = math.asin(sb)
    if abs(abs(sb) - 1.0) < 1e-9:
        # Gimbal lock: only a -/+ c is defined; put it all in a.
        c = 0.0
        a = math.atan2(-float(r[0, 1]), float(r[1, 1]))
    else:
        a = math.atan2(float(r[1, 0]), float(r[0, 0]))
        c = math.atan2(float(r[2, 1]), float(r[2, 2]))
    return a, b, c


def matrix(x_m: float, y_m: float, z_m: float, a_rad: float = 0.0, b_rad: float = 0.0, c_rad: float = 0.0) -> np.ndarray:
    """Homogeneous 4x4 transform of a pose."""
    t = np.eye(4)
    t[:3, :3] = rotation_zyx(a_rad, b_rad, c_rad)
    t[:3, 3] = (x_m, y_m, z_m)
    return t


@dataclass(frozen=True, slots=True)
class Pose:
    """A Cartesian pose relative to a named frame (world unless said otherwise)."""

    x: float                    #: m
    y: float                    #: m
    z: float                    #: m
    a: float = 0.0              #: rad, about z (applied first from the left)
    b: float = 0.0              #: rad, about y
    c: float = 0.0              #: rad, about x
    frame: str = WORLD          #: name of the on-line frame the numbers are relative to

    @classmethod
    def from_matrix(cls, t: np.ndarray, frame: str = WORLD) -> Pose:
        """The pose of a homogeneous transform."""
        a, b, c = zyx_angles(t[:3, :3])
        return cls(float(t[0, 3]), float(t[1, 3]), float(t[2, 3]), a, b, c, frame)

    def matrix(self) -> np.ndarray:
        """Homogeneous 4x4 transform."""
        return matrix(self.x, self.y, self.z, self.a, self.b, self.c)

    def compose(self, other: Pose) -> Pose:
        """self * other: `other` expressed in self's axes; the result keeps self's frame."""
        return Pose.from_matrix(self.matrix() @ other.matrix(), self.frame)

    def inverse(self) -> Pose:
        """INV(p): the inverse transform (its frame is the one it was relative to)."""
        return Pose.from_matrix(np.linalg.inv(self.matrix()), self.frame)

    def offset(self, dx_m: float, dy_m: float, dz_m: float) -> Pose:
        """OFFS(p, dx, dy, dz): displaced along the axes of the frame the pose is relative to."""
        return Pose(self.x + dx_m, self.y + dy_m, self.z + dz_m, self.a, self.b, self.c, self.frame)

    def reltool(self, dx_m: float, dy_m: float, dz_m: float) -> Pose:
        """RELTOOL(p, dx, dy, dz): displaced along the pose's own axes."""
        return self.compose(Pose(dx_m, dy_m, dz_m, frame=self.frame))

    def with_frame(self, frame: str) -> Pose:
        """The same numbers, relative to another frame."""
        return Pose(self.x, self.y, self.z, self.a, self.b, self.c, frame)


@dataclass(frozen=True, slots=True)
class Joints:
    """A joint-space position: one angle (rad) or length (m) per axis."""

    values: tuple[float, ...]

    def __len__(self) -> int:
        return len(self.values)


def _wrap(angle_rad: float) -> float:
    """An angle in (-pi, pi]."""
    wrapped = math.remainder(angle_rad, 2.0 * math.pi)
    return math.pi if math.isclose(wrapped, -math.pi, abs_tol=1e-12) else wrapped


def zyx_alternatives(a_rad: float, b_rad: float, c_rad: float) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """The two angle triples (a, b, c) of one rotation Rz(a)·Ry(b)·Rx(c), each wrapped to (-pi, pi]."""
    first = (_wrap(a_rad), _wrap(b_rad), _wrap(c_rad))
    second = (_wrap(a_rad + math.pi), _wrap(math.pi - b_rad), _wrap(c_rad + math.pi))
    return first, second


def readable_angles(pose: Pose, near: Pose | None = None) -> Pose:
    """The same pose with the angle triple a person would write: the one nearest `near`, else the one with fewest turns.

    `from_matrix` always returns |b| <= 90°, so a tool pointing down (0, 180°, 0) comes back as
    (180°, 0, 180°); a world file written by a person should get its own spelling back.
    """
    options = zyx_alternatives(pose.a, pose.b, pose.c)
    if near is not None:
        def cost(abc: tuple[float, float, float]) -> float:
            return sum(abs(_wrap(x - y)) for x, y in zip(abc, (near.a, near.b, near.c)))
    else:
        def cost(abc: tuple[float, float, float]) -> float:
            nonzero = sum(1 for x in abc if abs(x) > 1e-9)
            return nonzero * 100.0 + abs(abc[2]) * 10.0 + sum(abs(x) for x in abc)
    a, b, c = min(options, key=cost)
    return Pose(pose.x, pose.y, pose.z, a, b, c, pose.frame)
