"""Moving frames of the world: an object whose frame an external axis (track, positioner) or a conveyor moves."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from orc_rpl.syntax.units import (ACCELERATION, ANGLE, ANGULAR_ACCELERATION, ANGULAR_VELOCITY, LENGTH, VELOCITY,
                                  Dimension, Quantity, magnitude)
from orc_rpl.world.source import MappingNode, Node, ScalarNode, SequenceNode, did_you_mean
from orc_rpl.world.values import BadValue, read_number

#: The kinds of moving frame: a linear axis (a track), a rotary axis (a positioner's tilt or turn), a conveyor.
JOINTS = ("linear", "rotary", "conveyor")
DIRECTIONS = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}
AXIS_KEYS = ("joint", "direction", "range", "speed", "acceleration", "home")


@dataclass(frozen=True, slots=True)
class AxisSpec:
    """How a moving frame moves relative to its declared pose: along or about one of its own axes.

    The object's `pose` is where its frame is at axis value 0; at value v a linear axis (and a
    conveyor) has moved it by v along `direction`, a rotary axis has turned it by v about it. Values
    are m or rad; a conveyor's value is `speed_si * t`, it has no range and nothing commands it.
    """

    joint: str                                     #: linear | rotary | conveyor
    direction: str = "z"                           #: x | y | z of the object's frame
    range_si: tuple[float, float] = (-math.inf, math.inf)   #: lowest and highest value (m or rad)
    speed_si: float = 0.0                          #: highest speed (a conveyor: its speed), m/s or rad/s
    acceleration_si: float = 0.0                   #: highest acceleration, m/s2 or rad/s2 (a conveyor: 0)
    home_si: float = 0.0                           #: the value when the cell starts

    @property
    def rotary(self) -> bool:
        return self.joint == "rotary"

    def matrix(self, value: float) -> np.ndarray:
        """The frame's motion at axis value `value` (4x4, in the frame at value 0)."""
        return axis_matrix(self.direction, self.rotary, value)

    def clamp_message(self, value: float) -> str | None:
        """Why `value` is outside the axis' range, or None."""
        lo, hi = self.range_si
        if lo - 1e-12 <= value <= hi + 1e-12:
            return None
        unit, scale = ("deg", 180.0 / math.pi) if self.rotary else ("mm", 1000.0)
        return f"{value * scale:.6g}{unit} is outside its range {lo * scale:.6g}{unit}..{hi * scale:.6g}{unit}"


def axis_matrix(direction: str, rotary: bool, value: float) -> np.ndarray:
    """A translation by `value` along, or a rotation by `value` about, the unit axis `direction`."""
    t = np.eye(4)
    u = np.array(DIRECTIONS[direction])
    if not rotary:
        t[:3, 3] = u * value
        return t
    c, s = math.cos(value), math.sin(value)
    k = np.array([[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]])
    t[:3, :3] = np.eye(3) + s * k + (1.0 - c) * (k @ k)
    return t


def read_axis(node: Node, bad: Callable[[Node, str, str], None]) -> AxisSpec | None:
    """An `axis:` mapping of a world object; every mistake is reported through `bad(node, message, hint)`."""
    if not isinstance(node, MappingNode):
        bad(node, "'axis' is a mapping: joint, direction, range, speed, acceleration, home", "")
        return None
    keys: dict[str, tuple[ScalarNode, Node]] = {}
    for key, value in node.value:
        name = getattr(key, "value", None)
        if name not in AXIS_KEYS:
            bad(key, f"unknown axis attribute '{name}'", did_you_mean(str(name), list(AXIS_KEYS)) or "allowed: " + ", ".join(AXIS_KEYS))
        elif name in keys:
            bad(key, f"duplicate key '{name}'", f"first given at line {keys[name][0].start_mark.line + 1}")
        else:
            keys[name] = (key, value)
    if "joint" not in keys:
        bad(node, "an axis needs 'joint: linear', 'joint: rotary' or 'joint: conveyor'", "")
        return None
    jnode = keys["joint"][1]
    joint = jnode.value if isinstance(jnode, ScalarNode) else None
    if joint not in JOINTS:
        bad(jnode, f"unknown joint '{joint}'", did_you_mean(str(joint), list(JOINTS)) or "linear, rotary or conveyor")
        return None
    rotary = joint == "rotary"
    position, speed, accel = (ANGLE, ANGULAR_VELOCITY, ANGULAR_ACCELERATION) if rotary else (LENGTH, VELOCITY, ACCELERATION)
    ok = True
    direction = "z"
    if "direction" in keys:
        dnode = keys["direction"][1]
        direction = dnode.value if isinstance(dnode, ScalarNode) else ""
        if direction not in DIRECTIONS:
            bad(dnode, f"an axis' direction is x, y or z of the object's frame, got '{direction}'", "")
            ok = False
    required = ("speed",) if joint == "conveyor" else ("range", "speed", "acceleration")
    for name in required:
        if name not in keys:
            bad(node, f"a {joint} axis needs '{name}'", _EXAMPLES[joint])
            ok = False
    if joint == "conveyor":
        for name in ("range", "acceleration", "home"):
            if name in keys:
                bad(keys[name][0], f"a conveyor has no '{name}': it moves at its speed from the start", "")
                ok = False
    try:
        lo, hi = _range(keys["range"][1], position) if "range" in keys else (-math.inf, math.inf)
        speed_si = _quantity(keys["speed"][1], speed, "speed", signed=joint == "conveyor") if "speed" in keys else 0.0
        accel_si = _quantity(keys["acceleration"][1], accel, "acceleration") if "acceleration" in keys else 0.0
        home = _quantity(keys["home"][1], position, "home", signed=True) if "home" in keys else 0.0
    except BadValue as exc:
        bad(exc.node, exc.message, exc.hint)
        return None
    if not ok:
        return None
    if joint != "conveyor" and not lo <= home <= hi:
        bad(keys["home"][1] if "home" in keys else node, "the axis' home is outside its range",
            "give 'home:' a value inside 'range:' (the default home is 0)")
        return None
    return AxisSpec(joint, direction, (lo, hi), speed_si, accel_si, home)


_EXAMPLES = {
    "linear": "for example range: [0, 2000mm], speed: 1000mm/s, acceleration: 2000mm/s2",
    "rotary": "for example range: [-180deg, 180deg], speed: 90deg/s, acceleration: 360deg/s2",
    "conveyor": "for example speed: 100mm/s",
}


def _quantity(node: Node, dim: Dimension, what: str, signed: bool = False) -> float:
    value = read_number(node, f"the axis' {what}")
    if isinstance(value, Quantity) and value.dim != dim:
        raise BadValue(node, f"the axis' {what} must be {'an' if str(dim)[0] in 'aeiou' else 'a'} {dim}, got '{node.value}'")
    number = float(magnitude(value))
    if not signed and number <= 0.0:
        raise BadValue(node, f"the axis' {what} must be positive, got '{node.value}'")
    return number


def _range(node: Node, dim: Dimension) -> tuple[float, float]:
    if not isinstance(node, SequenceNode) or len(node.value) != 2:
        raise BadValue(node, "an axis' range is a list [lowest, highest]", "for example [0, 2000mm] or [-90deg, 90deg]")
    lo, hi = (_quantity(item, dim, "range", signed=True) for item in node.value)
    if not lo < hi:
        raise BadValue(node, "an axis' range needs its lowest value first and below the highest")
    return lo, hi
