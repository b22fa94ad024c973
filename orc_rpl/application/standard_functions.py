"""Behaviour of the standard functions: POSE, JOINTS, TRANSL, INV, OFFS, RELTOOL and ABS, ROUND, SQRT, SIN, COS, ATAN2, MIN, MAX, LEN."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import Any

from orc_rpl.application.runtime import BehaviourError
from orc_rpl.syntax import units
from orc_rpl.syntax.units import ANGLE, DIMENSIONLESS, LENGTH, Dimension, Quantity
from orc_rpl.world.pose import Joints, Pose


def _describe(value: Any) -> str:
    if isinstance(value, bool):
        return "TRUE/FALSE"
    if isinstance(value, (int, float)):
        return "a number"
    if isinstance(value, Quantity):
        return f"a {units.DIMENSION_NAMES.get(value.dim, value.dim.symbol())} ({value.dim.symbol()})"
    return {Pose: "a pose", Joints: "a joint position", tuple: "a list", str: "a string"}.get(type(value), type(value).__name__)


def si(value: Any, dim: Dimension, what: str) -> float:
    """The SI number of a length, angle...; a plain number is taken as SI (m, rad)."""
    if type(value) in (int, float):
        return float(value)
    if type(value) is Quantity and value.dim == dim:
        return value.value
    raise BehaviourError(f"{what} must be a {units.DIMENSION_NAMES.get(dim, dim.symbol())}, got {_describe(value)}")


def _pose(value: Any, function: str) -> Pose:
    if type(value) is not Pose:
        raise BehaviourError(f"{function} needs a pose, got {_describe(value)}")
    return value


def pose(x: Any, y: Any, z: Any, a: Any = 0, b: Any = 0, c: Any = 0) -> Pose:
    return Pose(si(x, LENGTH, "POSE x"), si(y, LENGTH, "POSE y"), si(z, LENGTH, "POSE z"),
                si(a, ANGLE, "POSE a"), si(b, ANGLE, "POSE b"), si(c, ANGLE, "POSE c"))


def axes(p: Any, **values: Any) -> Pose:
    """AXES(p, track = 200mm, turn = 90deg): the position p carrying external-axis values (m or rad)."""
    base = _pose(p, "AXES")
    if not values:
        raise BehaviourError("AXES needs at least one axis value, as in AXES(p, track = 200mm)")
    out = dict(base.axes)
    for name, value in values.items():
        if type(value) is Quantity and value.dim in (LENGTH, ANGLE):
            out[name] = value.value
        elif type(value) in (int, float):
            out[name] = float(value)
        else:
            raise BehaviourError(f"AXES: the value of axis '{name}' must be a length or an angle, got {_describe(value)}")
    return dataclasses.replace(base, axes=tuple(sorted(out.items())))


def joints(*values: Any) -> Joints:
    if not values:
        raise BehaviourError("JOINTS needs one value per axis")
    out = []
    for i, v in enumerate(values, 1):
        if type(v) is Quantity and v.dim == LENGTH:  # a linear axis
            out.append(v.value)
        else:
            out.append(si(v, ANGLE, f"JOINTS value {i}"))
    return Joints(tuple(out))


def transl(x: Any, y: Any, z: Any) -> Pose:
    return Pose(si(x, LENGTH, "TRANSL x"), si(y, LENGTH, "TRANSL y"), si(z, LENGTH, "TRANSL z"))


def inv(p: Any) -> Pose:
    return _pose(p, "INV").inverse()


def offs(p: Any, dx: Any, dy: Any, dz: Any) -> Pose:
    return _pose(p, "OFFS").offset(si(dx, LENGTH, "OFFS dx"), si(dy, LENGTH, "OFFS dy"), si(dz, LENGTH, "OFFS dz"))


def reltool(p: Any, dx: Any, dy: Any, dz: Any) -> Pose:
    return _pose(p, "RELTOOL").reltool(si(dx, LENGTH, "RELTOOL dx"), si(dy, LENGTH, "RELTOOL dy"), si(dz, LENGTH, "RELTOOL dz"))


def _scalar(value: Any, function: str) -> tuple[float, Dimension]:
    if type(value) in (int, float):
        return float(value), DIMENSIONLESS
    if type(value) is Quantity:
        return value.value, value.dim
    raise BehaviourError(f"{function} needs a number or a quantity, got {_describe(value)}")


def absolute(x: Any) -> Any:
    if type(x) in (int, float):
        return abs(x)
    value, dim = _scalar(x, "ABS")
    return Quantity(abs(value), dim)


def round_(x: Any, digits: Any = 0) -> Any:
    """Half away from zero, as a robot programmer expects (ROUND(2.5) = 3); ROUND(x) of a number is whole."""
    if type(digits) is not int and not (type(digits) is float and digits == int(digits)):
        raise BehaviourError(f"ROUND's digits must be a whole number, got {_describe(digits)}")
    value, dim = _scalar(x, "ROUND")
    scale = 10.0 ** int(digits)
    rounded = math.copysign(math.floor(abs(value) * scale + 0.5), value) / scale
    if dim.is_dimensionless:
        return int(rounded) if int(digits) <= 0 else rounded
    return Quantity(rounded, dim)


def sqrt(x: Any) -> Any:
    value, dim = _scalar(x, "SQRT")
    if value < 0:
        raise BehaviourError(f"SQRT of a negative value ({value:g})")
    exps = (dim.length, dim.mass, dim.time, dim.angle)
    if any(e % 2 for e in exps):
        raise BehaviourError(f"SQRT of {_describe(x)} has no unit")
    return units.quantity(math.sqrt(value), Dimension(*(e // 2 for e in exps)))


def _angle(x: Any, function: str) -> float:
    if type(x) is Quantity and x.dim == ANGLE:
        return x.value
    if type(x) in (int, float):
        return float(x)
    raise BehaviourError(f"{function} needs an angle, got {_describe(x)}")


def sin(x: Any) -> float:
    return math.sin(_angle(x, "SIN"))


def cos(x: Any) -> float:
    return math.cos(_angle(x, "COS"))


def atan2(y: Any, x: Any) -> Quantity:
    vy, dy = _scalar(y, "ATAN2")
    vx, dx = _scalar(x, "ATAN2")
    if dy != dx:
        raise BehaviourError(f"ATAN2 needs y and x of one dimension, got {_describe(y)} and {_describe(x)}")
    return Quantity(math.atan2(vy, vx), ANGLE)


def _extreme(values: tuple[Any, ...], function: str, pick: Callable[[float, float], bool]) -> Any:
    if len(values) == 1 and type(values[0]) is tuple:
        values = values[0]
    if not values:
        raise BehaviourError(f"{function} needs at least one value")
    best = values[0]
    best_value, best_dim = _scalar(best, function)
    for v in values[1:]:
        value, dim = _scalar(v, function)
        if dim != best_dim:
            raise BehaviourError(f"{function} cannot compare {_describe(best)} with {_describe(v)}")
        if pick(value, best_value):
            best, best_value = v, value
    return best


def minimum(*values: Any) -> Any:
    return _extreme(values, "MIN", lambda a, b: a < b)


def maximum(*values: Any) -> Any:
    return _extreme(values, "MAX", lambda a, b: a > b)


def length(items: Any) -> int:
    if type(items) in (tuple, str):
        return len(items)
    if type(items) is Joints:
        return len(items.values)
    raise BehaviourError(f"LEN needs a list, a path or a string, got {_describe(items)}")


#: name -> implementation, for the registry's `implementation` slots.
IMPLEMENTATIONS: dict[str, Callable[..., Any]] = {
    "POSE": pose, "AXES": axes, "JOINTS": joints, "TRANSL": transl, "INV": inv, "OFFS": offs, "RELTOOL": reltool,
    "ABS": absolute, "ROUND": round_, "SQRT": sqrt, "SIN": sin, "COS": cos, "ATAN2": atan2,
    "MIN": minimum, "MAX": maximum, "LEN": length,
}
