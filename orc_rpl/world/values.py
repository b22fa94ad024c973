"""Values written in world files: poses and quantities with the language's units, read from nodes and written back as text."""

from __future__ import annotations

import math
import re
from functools import lru_cache

from orc_rpl.errors import Diagnostic
from orc_rpl.syntax.units import ANGLE, LENGTH, Dimension, Quantity, Scalar, dim_of, format_number, magnitude, parse_literal
from orc_rpl.world.pose import Pose
from orc_rpl.world.source import Node, ScalarNode, SequenceNode, SourceText

#: What each of the six pose values measures; a plain number is SI (m, rad), as in POSE(...).
POSE_FIELDS: tuple[tuple[str, Dimension], ...] = (
    ("x", LENGTH), ("y", LENGTH), ("z", LENGTH), ("a", ANGLE), ("b", ANGLE), ("c", ANGLE),
)

#: Written poses are rounded here: 1 nm and 1e-9 deg keep affix/unfix far below any robot's repeatability.
LENGTH_DIGITS_MM = 6
ANGLE_DIGITS_DEG = 9

SoftValue = bool | int | float | str | Quantity | None


class BadValue(Exception):
    """A value that cannot be read, with the node to point at."""

    def __init__(self, node: Node, message: str, hint: str = "") -> None:
        super().__init__(message)
        self.node, self.message, self.hint = node, message, hint

    def diagnostic(self, src: SourceText) -> Diagnostic:
        return src.diagnostic(self.node, self.message, self.hint)


def read_number(node: Node, what: str) -> Scalar:
    """A number with an optional sign and unit (`-300mm`, `90deg`, `0.5`) from a scalar node."""
    if not isinstance(node, ScalarNode) or node.style not in (None, ""):
        raise BadValue(node, f"{what} must be a number with an optional unit")
    text = node.value.strip()
    try:
        value = _signed_literal(text)
    except KeyError:
        body = text[1:] if text[:1] in "+-" else text
        unit = re.sub(r"^[\d.eE+-]+", "", body)
        raise BadValue(node, f"unknown unit '{unit}' in '{text}'", "units: mm cm m deg rad (a plain number is m or rad)") from None
    except (ValueError, OverflowError):  # OverflowError: 400 digits with a unit
        raise BadValue(node, f"'{text}' is not a number", f"{what} is a number with an optional unit") from None
    if not math.isfinite(magnitude(value)):
        raise BadValue(node, f"'{text}' is not a finite number", f"{what} is a number with an optional unit")
    return value


@lru_cache(maxsize=8192)
def _signed_literal(text: str) -> Scalar:
    """`-300mm` as a value; world files repeat the same few numbers thousands of times."""
    sign = -1.0 if text.startswith("-") else 1.0
    value = parse_literal(text[1:] if text[:1] in "+-" else text)
    if sign < 0:
        return Quantity(-value.value, value.dim) if isinstance(value, Quantity) else -value
    return value


def read_pose(node: Node, frame: str) -> Pose:
    """`[x, y, z, a, b, c]` with units; plain numbers are m and rad. The pose is relative to `frame`."""
    if type(node) in _SEQUENCES and len(node.value) == 6:
        # the common case at the cost of a dictionary lookup: six plain scalars whose text was read before
        texts = tuple(item.value if type(item) in _SCALARS and not item.style else None for item in node.value)
        numbers = _POSES.get(texts)
        if numbers is not None:
            return Pose(*numbers, frame=frame)
        pose = _read_pose(node, frame)
        if None not in texts and len(_POSES) < 65536:
            _POSES[texts] = (pose.x, pose.y, pose.z, pose.a, pose.b, pose.c)
        return pose
    return _read_pose(node, frame)


#: Node classes of both YAML parsers, for the fast path of read_pose.
_SEQUENCES, _SCALARS = SequenceNode.classes, ScalarNode.classes
#: The six scalar texts of a pose -> its numbers (world files repeat the same poses; a few hundred distinct ones).
_POSES: dict[tuple[str | None, ...], tuple[float, ...]] = {}


def _read_pose(node: Node, frame: str) -> Pose:
    if not isinstance(node, SequenceNode):
        raise BadValue(node, "a pose is a list [x, y, z, a, b, c]", "for example [1200mm, 300mm, 750mm, 0, 0, 90deg]")
    if len(node.value) != 6:
        raise BadValue(node, f"a pose has 6 values [x, y, z, a, b, c], got {len(node.value)}")
    numbers = []
    for item, (name, dim) in zip(node.value, POSE_FIELDS):
        value = read_number(item, f"pose value {name}")
        if isinstance(value, Quantity) and value.dim != dim:
            raise BadValue(item, f"pose value {name} must be a{'n' if dim == ANGLE else ''} {dim}, got a{'n' if dim_of(value) == ANGLE else ''} {dim_of(value)} ('{item.value}')")
        numbers.append(magnitude(value))
    return Pose(*numbers, frame=frame)


def read_lengths(node: Node, what: str) -> tuple[float, ...]:
    """A list of lengths (`[600mm, 800mm, 20mm]`) in m."""
    if not isinstance(node, SequenceNode):
        raise BadValue(node, f"{what} is a list of lengths")
    out = []
    for item in node.value:
        value = read_number(item, what)
        if isinstance(value, Quantity) and value.dim != LENGTH:
            raise BadValue(item, f"{what} must be lengths, got a{'n' if value.dim == ANGLE else ''} {value.dim} ('{item.value}')")
        out.append(magnitude(value))
    return tuple(out)


def read_colour(node: Node) -> tuple[float, ...]:
    """`[0.8, 0.2, 0.2]` or with alpha: plain numbers from 0 to 1 (a colour name is read by the caller)."""
    if not isinstance(node, SequenceNode) or len(node.value) not in (3, 4):
        raise BadValue(node, "a colour is a name or a list [r, g, b] or [r, g, b, a] of numbers from 0 to 1")
    out = []
    for item in node.value:
        value = read_number(item, "colour")
        if isinstance(value, Quantity) or not 0.0 <= float(value) <= 1.0:
            raise BadValue(item, f"a colour value is a plain number from 0 to 1, got '{item.value}'")
        out.append(float(value))
    return tuple(out)


def read_soft(node: Node) -> SoftValue:
    """A soft attribute: true/false, a number (with a unit, kept as a Quantity), a string, or null."""
    if not isinstance(node, ScalarNode):
        raise BadValue(node, "a soft attribute is a single value (number, text, true/false)")
    tag = node.tag.rsplit(":", 1)[-1]
    if tag == "bool":
        return node.value.lower() in ("true", "yes", "on")
    if tag == "null":
        return None
    if tag in ("int", "float"):
        return _yaml_number(node, tag)
    if node.style in (None, "") and re.fullmatch(r"[+-]?(\d|\.\d)\S*", node.value):
        return read_number(node, "a soft attribute")
    return node.value


def _yaml_number(node: ScalarNode, tag: str) -> int | float:
    """A YAML int (`12`, `0x1F`) or float (`0.5`); `.nan`, `.inf` and what Python cannot read are BadValue."""
    text = node.value.replace("_", "")
    try:
        value: int | float = int(text, 0) if tag == "int" else float(text)
    except ValueError:
        raise BadValue(node, f"'{node.value}' is not a number this file can use", "write a decimal number") from None
    if isinstance(value, float) and not math.isfinite(value):
        raise BadValue(node, f"'{node.value}' is not a finite number")
    return value


def _fixed(value: float, digits: int) -> str:
    """Shortest text of a value rounded to `digits` decimals (no `-0`)."""
    rounded = round(value, digits)
    if rounded == 0:
        return "0"
    return format_number(rounded)


def format_length(value_m: float) -> str:
    """A length as a world file writes it: `300mm`, `0` (millimetres, the unit cell drawings use)."""
    text = _fixed(value_m * 1000.0, LENGTH_DIGITS_MM)
    return "0" if text == "0" else f"{text}mm"


def format_angle(value_rad: float) -> str:
    """An angle as a world file writes it: `90deg`, `0`."""
    text = _fixed(math.degrees(value_rad), ANGLE_DIGITS_DEG)
    return "0" if text == "0" else f"{text}deg"


def format_pose(pose: Pose, rotary: frozenset[str] | set[str] = frozenset()) -> str:
    """`[1200mm, 300mm, 750mm, 0, 0, 90deg]`: the flow list a world file writes for a pose; a position with
    external-axis values gets them last, `{track: 200mm, turn: 90deg}` (`rotary`: the axes that take angles)."""
    parts = [format_length(v) for v in (pose.x, pose.y, pose.z)] + [format_angle(v) for v in (pose.a, pose.b, pose.c)]
    if pose.axes:
        parts.append("{" + ", ".join(f"{k}: {format_angle(v) if k in rotary else format_length(v)}" for k, v in pose.axes) + "}")
    return "[" + ", ".join(parts) + "]"


def format_soft(value: SoftValue) -> str:
    """A soft attribute's YAML text."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return format_number(value)
    if isinstance(value, Quantity):
        return f"{format_number(value.value)}{value.dim.symbol()}"
    if re.fullmatch(r"[A-Za-z_][A-Za-z0-9_ .-]*", value) and value.lower() not in ("true", "false", "yes", "no", "on", "off", "null"):
        return value
    return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
