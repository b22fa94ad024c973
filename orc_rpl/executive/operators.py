"""RPL's operators on run-time values: fast paths for plain numbers, units checked for quantities, poses composed."""

from __future__ import annotations

from typing import Any

from orc_rpl.executive.signals import RunError
from orc_rpl.application.values import Record
from orc_rpl.executive.values import EnumValue, type_name
from orc_rpl.syntax import units
from orc_rpl.syntax.units import DimensionError, Quantity
from orc_rpl.world.pose import Joints, Pose


def _fail(message: str) -> RunError:
    return RunError(message)


def truth(value: Any) -> bool:
    """A condition's value: TRUE/FALSE, or a digital input's 0/1."""
    if value is True or value is False:
        return value
    if (type(value) is int or type(value) is float) and (value == 0 or value == 1):
        return bool(value)
    raise _fail(f"expected TRUE or FALSE, got {type_name(value)}")


def _scalar(value: Any) -> bool:
    t = type(value)
    return t is int or t is float or t is Quantity


def add(a: Any, b: Any) -> Any:
    ta, tb = type(a), type(b)
    if (ta is int or ta is float) and (tb is int or tb is float):
        return a + b
    if _scalar(a) and _scalar(b):
        return _units(units.add, a, b, "+")
    if ta is str and tb is str:
        return a + b
    if ta is tuple and tb is tuple:
        return a + b
    raise _fail(f"cannot add {type_name(a)} and {type_name(b)}")


def subtract(a: Any, b: Any) -> Any:
    ta, tb = type(a), type(b)
    if (ta is int or ta is float) and (tb is int or tb is float):
        return a - b
    if _scalar(a) and _scalar(b):
        return _units(units.add, a, b, "-")
    raise _fail(f"cannot subtract {type_name(b)} from {type_name(a)}")


def multiply(a: Any, b: Any) -> Any:
    ta, tb = type(a), type(b)
    if (ta is int or ta is float) and (tb is int or tb is float):
        return a * b
    if _scalar(a) and _scalar(b):
        return units.multiply(a, b)
    if ta is Pose and tb is Pose:
        return a.compose(b)
    raise _fail(f"cannot multiply {type_name(a)} by {type_name(b)}")


def divide(a: Any, b: Any) -> Any:
    if _scalar(a) and _scalar(b):
        if units.magnitude(b) == 0:
            raise _fail("division by zero")
        return units.divide(a, b)
    raise _fail(f"cannot divide {type_name(a)} by {type_name(b)}")


def negate(a: Any) -> Any:
    t = type(a)
    if t is int or t is float:
        return -a
    if t is Quantity:
        return Quantity(-a.value, a.dim)
    raise _fail(f"cannot negate {type_name(a)}")


def _units(fn: Any, a: Any, b: Any, op: str) -> Any:
    try:
        return fn(a, b, op)
    except DimensionError as error:
        raise _fail(str(error)) from None


def equal(a: Any, b: Any) -> bool:
    """`a = b`: numbers and quantities of one dimension, strings, booleans, ENUM values, poses, lists."""
    ta, tb = type(a), type(b)
    if (ta is int or ta is float) and (tb is int or tb is float):
        return a == b
    if _scalar(a) and _scalar(b):
        _compare_dims(a, b)
        return units.magnitude(a) == units.magnitude(b)
    if (ta is bool and (tb is int or tb is bool)) or (tb is bool and ta is int):
        return int(a) == int(b)  # DigIn[1] = TRUE
    if ta is not tb:
        if {ta, tb} <= {EnumValue, int}:
            raise _fail(f"cannot compare {type_name(a)} with {type_name(b)}")
        raise _fail(f"cannot compare {type_name(a)} with {type_name(b)}")
    if ta is tuple:
        return len(a) == len(b) and all(equal(x, y) for x, y in zip(a, b))
    return a == b


def _compare_dims(a: Any, b: Any) -> None:
    try:
        units.compare_dims(a, b)
    except DimensionError as error:
        raise _fail(str(error)) from None


def _ordered(a: Any, b: Any) -> tuple[Any, Any]:
    ta, tb = type(a), type(b)
    if _scalar(a) and _scalar(b):
        _compare_dims(a, b)
        return units.magnitude(a), units.magnitude(b)
    if ta is str and tb is str:
        return a, b
    if ta is EnumValue and tb is EnumValue and a.enum == b.enum:
        return a.ordinal, b.ordinal
    raise _fail(f"cannot order {type_name(a)} and {type_name(b)}")


def less(a: Any, b: Any) -> bool:
    ta, tb = type(a), type(b)
    if (ta is int or ta is float) and (tb is int or tb is float):
        return a < b
    x, y = _ordered(a, b)
    return x < y


def less_equal(a: Any, b: Any) -> bool:
    ta, tb = type(a), type(b)
    if (ta is int or ta is float) and (tb is int or tb is float):
        return a <= b
    x, y = _ordered(a, b)
    return x <= y


def greater(a: Any, b: Any) -> bool:
    return less(b, a)


def greater_equal(a: Any, b: Any) -> bool:
    return less_equal(b, a)


BINARY = {
    "+": add, "-": subtract, "*": multiply, "/": divide,
    "=": equal, "<>": lambda a, b: not equal(a, b),
    "<": less, "<=": less_equal, ">": greater, ">=": greater_equal,
}

POSE_FIELDS = {"x": units.LENGTH, "y": units.LENGTH, "z": units.LENGTH, "a": units.ANGLE, "b": units.ANGLE, "c": units.ANGLE}


def list_index(items: Any, index: Any) -> int:
    """The 0-based position of RPL index `index` (from 1; an ENUM value counts from 1) in `items`."""
    if type(index) is int:
        i = index
    elif type(index) is EnumValue:
        i = index.ordinal
    elif type(index) is float and index == int(index):
        i = int(index)
    else:
        raise _fail(f"a list index must be a whole number or an ENUM value, got {type_name(index)}")
    if not 1 <= i <= len(items):
        raise _fail(f"index {i} is out of range: the list has {len(items)} element{'s' if len(items) != 1 else ''} (indices start at 1)")
    return i - 1


def get_field(value: Any, name: str) -> Any:
    """`value.name` for a pose or a record."""
    t = type(value)
    if t is Pose:
        dim = POSE_FIELDS.get(name)
        if dim is None:
            raise _fail(f"a pose has the fields x, y, z, a, b, c, not '{name}'")
        return Quantity(getattr(value, name), dim)
    if t is Record:
        try:
            return value.get(name)
        except KeyError:
            raise _fail(f"{value.type_name} has no field '{name}'; its fields: {', '.join(k for k, _ in value.fields)}") from None
    if t is Joints:
        raise _fail(f"a joint position has no field '{name}'; index it: q[1]")
    raise _fail(f"{type_name(value)} has no field '{name}'")


def set_field(value: Any, name: str, new: Any) -> Any:
    """A copy of the pose or record `value` with field `name` set to `new`."""
    t = type(value)
    if t is Pose:
        dim = POSE_FIELDS.get(name)
        if dim is None:
            raise _fail(f"a pose has the fields x, y, z, a, b, c, not '{name}'")
        number = as_si(new, dim, f"pose field {name}")
        fields = {k: getattr(value, k) for k in "xyzabc"}
        fields[name] = number
        return Pose(**fields, frame=value.frame)
    if t is Record:
        return value.replace(name, new)
    raise _fail(f"cannot set field '{name}' of {type_name(value)}")


def as_si(value: Any, dim: units.Dimension, what: str) -> float:
    """The SI number of `value`, which must have dimension `dim` (a plain number is taken as SI)."""
    t = type(value)
    if t is int or t is float:
        return float(value)
    if t is Quantity:
        if value.dim != dim:
            raise _fail(f"{what} must be {_dim_word(dim)}, got {type_name(value)}")
        return value.value
    raise _fail(f"{what} must be {_dim_word(dim)}, got {type_name(value)}")


def _dim_word(dim: units.Dimension) -> str:
    word = units.DIMENSION_NAMES.get(dim, dim.symbol())
    return f"a {word} ({dim.symbol()})" if not dim.is_dimensionless else "a number"
