"""Pose literals in programs: `POSE(50mm, -40mm, 60mm, -90deg, 180deg, 0)` from a Pose, and back."""

from __future__ import annotations

import dataclasses
from functools import lru_cache

from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.units import ANGLE, LENGTH, Quantity, parse_literal
from orc_rpl.world import WORLD, Pose, World
from orc_rpl.world.objects import FLANGE
from orc_rpl.world.pose import readable_angles
from orc_rpl.world.values import format_angle, format_length


@lru_cache(maxsize=4096)
def _number(text: str) -> n.Expression:
    """`-40mm` as the parser reads it: a minus applied to `40mm` (nodes are immutable, so equal ones are shared)."""
    if text.startswith("-"):
        return n.Unary("-", n.Number(text[1:]))
    return n.Number(text)


def pose_literal(pose: Pose, rotary: frozenset[str] | set[str] = frozenset()) -> n.Call:
    """`POSE(x, y, z, a, b, c)` in mm and deg, as world files write poses; a position with external-axis values is
    `AXES(POSE(...), track = 200mm, turn = 90deg)` (`rotary`: the axes whose values are angles)."""
    texts = [format_length(v) for v in (pose.x, pose.y, pose.z)] + [format_angle(v) for v in (pose.a, pose.b, pose.c)]
    literal = n.Call(n.Name("POSE"), tuple(n.Argument(None, _number(t)) for t in texts))
    if not pose.axes:
        return literal
    values = tuple(n.Argument(n.Name(k), _number(format_angle(v) if k in rotary else format_length(v))) for k, v in pose.axes)
    return n.Call(n.Name("AXES"), (n.Argument(None, literal),) + values)


def rotary_axes(world: World) -> frozenset[str]:
    """The world's rotary axes (their values are angles)."""
    return frozenset(name for name in world.moving_frames() if world.object(name).axis.rotary)  # type: ignore[union-attr]


def _value(expr: n.Expression) -> float | Quantity | None:
    sign = 1.0
    if isinstance(expr, n.Unary) and expr.op in "+-":
        sign, expr = (-1.0 if expr.op == "-" else 1.0), expr.operand
    if not isinstance(expr, n.Number):
        return None
    try:
        value = parse_literal(expr.text)
    except (KeyError, ValueError):
        return None
    if isinstance(value, Quantity):
        return Quantity(sign * value.value, value.dim)
    return sign * float(value)


def literal_pose(expr: n.Expression, frame: str = WORLD) -> Pose | None:
    """The Pose of a literal `POSE(...)` with six numbers (lengths then angles), or of `AXES(POSE(...), name = value, ...)`
    with literal values, or None for anything else."""
    if (isinstance(expr, n.Call) and expr.function == n.Name("AXES") and expr.arguments and expr.arguments[0].name is None
            and len(expr.arguments) > 1 and all(a.name is not None for a in expr.arguments[1:])):
        inner = literal_pose(expr.arguments[0].value, frame)
        values = [(a.name.id, _value(a.value)) for a in expr.arguments[1:]]  # type: ignore[union-attr]
        if inner is None or inner.axes or any(v is None for _, v in values):
            return None
        axes = tuple((k, v.value if isinstance(v, Quantity) else float(v)) for k, v in values)  # type: ignore[union-attr,arg-type]
        return dataclasses.replace(inner, axes=axes)
    if not (isinstance(expr, n.Call) and expr.function == n.Name("POSE") and len(expr.arguments) == 6):
        return None
    numbers = []
    for i, argument in enumerate(expr.arguments):
        if argument.name is not None:
            return None
        value = _value(argument.value)
        if value is None:
            return None
        if isinstance(value, Quantity):
            if value.dim != (LENGTH if i < 3 else ANGLE):
                return None
            value = value.value
        numbers.append(float(value))
    return Pose(*numbers, frame=frame)


def literal_path(expr: n.Expression, frame: str = WORLD) -> tuple[Pose, ...] | None:
    """The poses of `[POSE(...), ...]`, or None."""
    if not isinstance(expr, n.ListExpr) or not expr.items:
        return None
    poses = tuple(literal_pose(item, frame) for item in expr.items)
    return None if any(p is None for p in poses) else poses  # type: ignore[return-value]


def _nearest_tagged(world: World, names: tuple[str, ...]) -> str:
    for name in names:
        if name not in (WORLD, "robot", FLANGE) and (world.object(name).online_frame or world.object(name).axis is not None):
            return name  # a moving frame is an on-line frame the cell gives
    return WORLD


def object_pose(world: World, name: str) -> tuple[Pose, str]:
    """An object's pose relative to its on-line frame (the nearest tagged proper ancestor), and that frame."""
    obj = world.object(name)
    frame = _nearest_tagged(world, world.ancestors(name))
    if obj.parent == frame:
        return obj.pose.with_frame(frame), frame
    return readable_angles(world.relative_pose(name, frame), obj.pose), frame


def frame_pose(world: World, dotted: str) -> tuple[Pose, str]:
    """A named frame's pose relative to its on-line frame, and that frame."""
    owner, name = dotted.split(".")
    stored = world.object(owner).frame(name).pose  # type: ignore[union-attr]
    frame = _nearest_tagged(world, (owner,) + world.ancestors(owner))
    if frame == owner:
        return stored.with_frame(frame), frame
    return dataclasses.replace(readable_angles(world.relative_pose(dotted, frame), stored), axes=stored.axes), frame


def path_poses(world: World, dotted: str) -> tuple[tuple[Pose, ...], str]:
    """A path's poses relative to its on-line frame, and that frame."""
    owner, name = dotted.split(".")
    path = world.object(owner).path(name)
    frame = _nearest_tagged(world, (owner,) + world.ancestors(owner))
    if frame == owner:
        return tuple(p.with_frame(frame) for p in path.points), frame  # type: ignore[union-attr]
    base = world.relative_pose(owner, frame)
    return tuple(readable_angles(base.compose(p), p) for p in path.points), frame  # type: ignore[union-attr]


def tool_pose(world: World, name: str) -> Pose:
    """ARM*holder*grinder collapsed: the tool's pose relative to the flange."""
    obj = world.object(name)
    if obj.parent == FLANGE:
        return obj.pose.with_frame(FLANGE)
    return readable_angles(world.tool_pose(name), obj.pose)
