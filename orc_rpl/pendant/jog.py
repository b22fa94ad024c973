"""Jogging: small joint or Cartesian motions (world, tool or an on-line frame) from the robot's commanded position."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from orc_rpl.errors import OrcError
from orc_rpl.motion import CartesianMotion, JointMotion, MotionLayer, Params
from orc_rpl.syntax.units import ANGLE, LENGTH, dim_of, magnitude, parse_literal
from orc_rpl.world.pose import Pose

#: Cartesian axes: translations along x y z, rotations about x y z (about the TCP).
CARTESIAN_AXES = ("x", "y", "z", "rx", "ry", "rz")
#: Jog speeds at 100 % override; manual mode caps the TCP at 250 mm/s anyway.
JOG_TCP_SPEED_M_S = 0.25
JOG_JOINT_SPEED_FRACTION = 0.2
#: Increments of step jogging (F3 cycles through them), then continuous jogging.
STEPS = (("1mm / 1deg", 0.001, math.radians(1.0)), ("0.1mm / 0.1deg", 0.0001, math.radians(0.1)))
#: In continuous jogging each key press (keyboard auto-repeat, about 30 per second) adds this much motion.
CONTINUOUS = ("continuous", 0.008, math.radians(0.8))


class JogError(OrcError):
    """A jog command the pendant cannot carry out; nothing moved."""


@dataclass(frozen=True, slots=True)
class Jog:
    """One jog: in `space` ("joint", "world", "tool" or "frame"), along `axis`, by `amount` (m or rad)."""

    space: str
    axis: str                 #: "1".."6" for joints, else one of CARTESIAN_AXES
    amount: float             #: SI: m for translations, rad for rotations and revolute joints
    frame: str = "world"      #: the on-line frame for space "frame"


def parse_amount(text: str, rotation: bool) -> float:
    """`+5deg`, `-2mm`, `0.1` (SI) -> a length in m or an angle in rad, checked against the axis."""
    body = text[1:] if text.startswith("+") else text
    try:
        value = parse_literal(body[1:]) if body.startswith("-") else parse_literal(body)
    except Exception:  # the unit parser's errors vary (unknown unit, bad number): one message for all
        raise JogError(f"cannot read the amount {text!r}; write it like +10mm or -5deg") from None
    wanted = ANGLE if rotation else LENGTH
    dimension = dim_of(value)
    if dimension not in (wanted, dim_of(1.0)):
        raise JogError(f"the amount {text!r} must be {'an angle (deg)' if rotation else 'a length (mm)'}")
    number = magnitude(value)
    if not math.isfinite(number):  # `-1e999mm`: a number, but no distance the robot can go
        raise JogError(f"the amount {text!r} is not a finite number; write it like +10mm or -5deg")
    return -number if body.startswith("-") else number


def jog_motion(layer: MotionLayer, jog: Jog, tool: np.ndarray | None, frame_world: np.ndarray) -> JointMotion | CartesianMotion:
    """The motion of one jog, from where the robot will be when the motions already given are done."""
    q = np.array(layer.planned_end_q())
    if jog.space == "joint":
        index = int(jog.axis) - 1
        if not 0 <= index < len(q):
            raise JogError(f"joint {jog.axis}: the robot has joints 1 to {len(q)}")
        q[index] += jog.amount
        return JointMotion(target_rad=tuple(q), tool=tool)
    start = layer.fk(q, tool)
    if jog.space == "tool":
        axes = start[:3, :3]
    elif jog.space == "frame":
        axes = frame_world[:3, :3]
    else:
        axes = np.eye(3)
    target = start.copy()
    unit = np.eye(3)["xyz".index(jog.axis[-1])]
    if jog.axis.startswith("r"):
        rotation = _axis_rotation(axes @ unit, jog.amount)
        target[:3, :3] = rotation @ start[:3, :3]
    else:
        target[:3, 3] = start[:3, 3] + axes @ unit * jog.amount
    return CartesianMotion(target=Pose.from_matrix(target), kind="linear", tool=tool)


def jog_params(jog: Jog, override: float) -> Params:
    if jog.space == "joint":
        return Params(speed_fraction=JOG_JOINT_SPEED_FRACTION * override)
    return Params(speed_m_s=JOG_TCP_SPEED_M_S * override)


def _axis_rotation(axis: np.ndarray, angle_rad: float) -> np.ndarray:
    """Rotation by angle about a unit axis (Rodrigues)."""
    x, y, z = axis / np.linalg.norm(axis)
    k = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    return np.eye(3) + math.sin(angle_rad) * k + (1.0 - math.cos(angle_rad)) * (k @ k)


__all__ = ["CARTESIAN_AXES", "CONTINUOUS", "STEPS", "Jog", "JogError", "jog_motion", "jog_params", "parse_amount"]
