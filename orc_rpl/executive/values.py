"""Run-time values of RPL beyond numbers and quantities: ENUM values, records, IO channels, installed objects; PRINT's text."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from orc_rpl.application.runtime import FINE, Fine
from orc_rpl.application.values import Record
from orc_rpl.syntax.units import ANGLE as _ANGLE, DIMENSION_NAMES, LENGTH as _LENGTH, Quantity, format_number
from orc_rpl.world.pose import Joints, Pose


@dataclass(frozen=True, slots=True)
class EnumType:
    """An `ENUM Part = NoObject, Bolt, Nut` declaration: its ordered members."""

    name: str
    members: tuple[str, ...]


@dataclass(frozen=True, slots=True, eq=False)
class EnumValue:
    """One ENUM member; ordered within its ENUM, the first is 1 as a list index."""

    enum: str        #: the ENUM's name
    name: str        #: the member's name
    ordinal: int     #: 1-based position

    def __eq__(self, other: object) -> bool:
        return isinstance(other, EnumValue) and other.enum == self.enum and other.ordinal == self.ordinal

    def __hash__(self) -> int:
        return hash((self.enum, self.ordinal))


@dataclass(frozen=True, slots=True)
class IOBank:
    """`DigIn`, `DigOut`, `AnalogIn` or `AnalogOut`: indexed to read or write a channel."""

    name: str                   #: the language's name
    digital: bool
    output: bool


@dataclass(frozen=True, slots=True)
class IOChannel:
    """One channel such as `DigOut[3]`, as an INSTALL attribute names it."""

    bank: IOBank
    number: int

    def __str__(self) -> str:
        return f"{self.bank.name}[{self.number}]"


IO_BANKS: dict[str, IOBank] = {
    "DigIn": IOBank("DigIn", True, False),
    "DigOut": IOBank("DigOut", True, True),
    "AnalogIn": IOBank("AnalogIn", False, False),
    "AnalogOut": IOBank("AnalogOut", False, True),
}


@dataclass(frozen=True, slots=True)
class Routine:
    """A PROC or FUNC as a value (an attribute given a FUNC name, a call)."""

    name: str
    kind: str                   #: PROC or FUNC
    params: tuple[str, ...]


@dataclass(slots=True)
class Installed:
    """An object made by `INSTALL name AS Kind`: its kind, attributes and behaviour (the kind's factory)."""

    name: str
    kind: str
    attributes: dict[str, Any]
    behaviour: Any = None                      #: what the kind's factory made (methods are looked up on it)
    tool: Pose | None = None                   #: when installed on a TOOL: the tool it is mounted as
    state: dict[str, Any] = field(default_factory=dict)


class RobotSignals:
    """The predefined `ROBOT`: software sensors (`ROBOT.Joints`, `ROBOT.Torque[j]`)."""

    __slots__ = ()


ROBOT = RobotSignals()


def format_value(value: Any, nested: bool = False) -> str:
    """A value as PRINT writes it (docs/language.md section 6); strings are quoted only inside lists."""
    if value is True:
        return "TRUE"
    if value is False:
        return "FALSE"
    kind = type(value)
    if kind is int or kind is float:
        return format_number(value)
    if kind is str:
        return '"' + value + '"' if nested else value
    if kind is Quantity:
        return str(value)
    if kind is tuple or kind is list:
        return "[" + ", ".join(format_value(v, True) for v in value) + "]"
    if kind is EnumValue or kind is EnumType:
        return value.name
    if kind is Pose:
        numbers = [Quantity(value.x, _LENGTH), Quantity(value.y, _LENGTH), Quantity(value.z, _LENGTH),
                   Quantity(value.a, _ANGLE), Quantity(value.b, _ANGLE), Quantity(value.c, _ANGLE)]
        text = "POSE(" + ", ".join(str(q) for q in numbers) + ")"
        if value.axes:  # external-axis values, plain numbers in SI (m for a linear axis, rad for a rotary one)
            text = "AXES(" + text + "".join(f", {k} = {round(v, 12) + 0.0!r}" for k, v in value.axes) + ")"
        return text if value.frame == "world" else f"{text} IN {value.frame}"
    if kind is Joints:
        return "JOINTS(" + ", ".join(str(Quantity(v, _ANGLE)) for v in value.values) + ")"
    if kind is Record:
        return value.type_name + "(" + ", ".join(f"{k} = {format_value(v, True)}" for k, v in value.fields) + ")"
    if kind is Installed:
        return value.name
    if kind is Routine:
        return value.name
    if kind is IOChannel:
        return str(value)
    if kind is IOBank:
        return value.name
    if value is FINE:
        return "FINE"
    if value is ROBOT:
        return "ROBOT"
    return str(value)


def type_name(value: Any) -> str:
    """How messages name the type of a value: `a number`, `a length`, `a pose`, `a list`."""
    if isinstance(value, bool):
        return "TRUE/FALSE"
    if isinstance(value, (int, float)):
        return "a number"
    if isinstance(value, Quantity):
        word = DIMENSION_NAMES.get(value.dim, value.dim.symbol())
        return f"a {word} ({value.dim.symbol()})"
    names = {str: "a string", tuple: "a list", list: "a list", Pose: "a pose", Joints: "a joint position",
             EnumValue: "an ENUM value", Record: "a record", Installed: "an installed object", Routine: "a routine",
             IOBank: "an IO bank", IOChannel: "an IO channel", Fine: "FINE", RobotSignals: "ROBOT"}
    return names.get(type(value), type(value).__name__)

