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
    #: external-axis values the position carries (`AXES(p, track = 200mm)`), by axis name, in m or rad
    axes: tuple[tuple[str, float], ...] = ()

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
        return Pose(self.x, self.y, self.z, self.a, self.b, self.c, frame, self.axes)


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


@dataclass(frozen=True, slots=True)
class ShownPose:
    """A pose as people read it (display only): mm and deg, rounded, in the convention of `shown_pose`."""

    x_mm: float
    y_mm: float
    z_mm: float
    a_deg: float
    b_deg: float
    c_deg: float
    frame: str = WORLD
    mm_digits: int = 1          #: decimals the numbers were rounded to
    deg_digits: int = 1

    def text(self) -> str:
        """`(1000.0, 0.0, 800.0) mm, (0.0, 180.0, 0.0) deg`."""
        xyz = ", ".join(f"{v:.{self.mm_digits}f}" for v in (self.x_mm, self.y_mm, self.z_mm))
        abc = ", ".join(f"{v:.{self.deg_digits}f}" for v in (self.a_deg, self.b_deg, self.c_deg))
        return f"({xyz}) mm, ({abc}) deg"


def _shown(value: float, digits: int) -> float:
    """Rounded to `digits` decimals, never -0.0."""
    return round(value, digits) + 0.0


def _shown_angle(angle_rad: float, digits: int) -> float:
    """Degrees rounded to `digits` decimals in (-180, 180]: -180 is shown as 180, -0 as 0."""
    degrees = _shown(math.degrees(_wrap(angle_rad)), digits)
    return 180.0 if degrees == -180.0 else degrees


def shown_pose(pose: Pose, mm_digits: int = 1, deg_digits: int = 1) -> ShownPose:
    """The one way a measured pose is shown to people (summaries, diffs, hovers, the pendant, the view, plots).

    Of the two angle triples of one rotation Rz(a)·Ry(b)·Rx(c), show the one with the fewest angles
    that are not zero at the shown precision, then the smaller |c|, then the smaller |b|; every angle
    in (-180, 180] deg and no -0. A tool pointing down declared (0, 180deg, 0) is measured as
    (180, ~0, 180) by `from_matrix` and shown as (0.0, 180.0, 0.0) again. Display only: program
    text keeps what the programmer wrote.
    """
    def shown(abc: tuple[float, float, float]) -> tuple[float, float, float]:
        a, b, c = (_shown_angle(v, deg_digits) for v in abc)
        return a, b, c

    def cost(abc: tuple[float, float, float]) -> tuple[int, float, float]:
        return sum(1 for v in abc if v != 0.0), abs(abc[2]), abs(abc[1])

    a, b, c = min((shown(option) for option in zyx_alternatives(pose.a, pose.b, pose.c)), key=cost)
    x, y, z = (_shown(v * 1000.0, mm_digits) for v in (pose.x, pose.y, pose.z))
    return ShownPose(x, y, z, a, b, c, pose.frame, mm_digits, deg_digits)
