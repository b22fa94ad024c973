"""Units of the language: the unit table, dimensions, and SI quantities whose arithmetic checks dimensions."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Dimension:
    """Exponents of length, mass, time and angle (angle is kept apart so `90deg` is not a plain number)."""

    length: int = 0
    mass: int = 0
    time: int = 0
    angle: int = 0

    def __mul__(self, other: Dimension) -> Dimension:
        return Dimension(self.length + other.length, self.mass + other.mass, self.time + other.time, self.angle + other.angle)

    def __truediv__(self, other: Dimension) -> Dimension:
        return Dimension(self.length - other.length, self.mass - other.mass, self.time - other.time, self.angle - other.angle)

    def __pow__(self, exponent: int) -> Dimension:
        return Dimension(self.length * exponent, self.mass * exponent, self.time * exponent, self.angle * exponent)

    @property
    def is_dimensionless(self) -> bool:
        return self == DIMENSIONLESS

    def __str__(self) -> str:
        return DIMENSION_NAMES.get(self) or self.symbol()

    def symbol(self) -> str:
        """The SI unit of this dimension, as PRINT shows it (`m/s`, `N`, `rad/s`)."""
        if self in SI_SYMBOLS:
            return SI_SYMBOLS[self]
        num, den = [], []
        for sym, exp in (("kg", self.mass), ("m", self.length), ("rad", self.angle), ("s", self.time)):
            target = num if exp > 0 else den
            if exp:
                target.append(sym if abs(exp) == 1 else f"{sym}{abs(exp)}")
        text = "*".join(num) or "1"
        return text + ("/" + "/".join(den) if den else "")


DIMENSIONLESS = Dimension()
LENGTH = Dimension(length=1)
MASS = Dimension(mass=1)
TIME = Dimension(time=1)
ANGLE = Dimension(angle=1)
VELOCITY = LENGTH / TIME
ANGULAR_VELOCITY = ANGLE / TIME
ACCELERATION = VELOCITY / TIME
ANGULAR_ACCELERATION = ANGULAR_VELOCITY / TIME
FORCE = MASS * ACCELERATION
TORQUE = FORCE * LENGTH

#: Names used in messages ("expected a velocity, got a force").
DIMENSION_NAMES: dict[Dimension, str] = {
    DIMENSIONLESS: "number",
    LENGTH: "length",
    MASS: "mass",
    TIME: "time",
    ANGLE: "angle",
    VELOCITY: "velocity",
    ANGULAR_VELOCITY: "angular velocity",
    ACCELERATION: "acceleration",
    ANGULAR_ACCELERATION: "angular acceleration",
    FORCE: "force",
    TORQUE: "torque",
}

#: SI symbol printed after a quantity's value.
SI_SYMBOLS: dict[Dimension, str] = {
    LENGTH: "m",
    MASS: "kg",
    TIME: "s",
    ANGLE: "rad",
    VELOCITY: "m/s",
    ANGULAR_VELOCITY: "rad/s",
    ACCELERATION: "m/s2",
    ANGULAR_ACCELERATION: "rad/s2",
    FORCE: "N",
    TORQUE: "Nm",
}

#: Every unit a literal may carry: name -> (SI factor, dimension). docs/language.md section 1,
#: plus the angular accelerations a joint ACCEL needs. Decimal prefixes are applied by
#: division (see `to_si`) so that `300mm` is exactly the float 0.3.
UNITS: dict[str, tuple[float, Dimension]] = {
    "mm": (1e-3, LENGTH),
    "cm": (1e-2, LENGTH),
    "m": (1.0, LENGTH),
    "deg": (math.pi / 180.0, ANGLE),
    "rad": (1.0, ANGLE),
    "ms": (1e-3, TIME),
    "s": (1.0, TIME),
    "mm/s": (1e-3, VELOCITY),
    "m/s": (1.0, VELOCITY),
    "mps": (1.0, VELOCITY),
    "deg/s": (math.pi / 180.0, ANGULAR_VELOCITY),
    "rad/s": (1.0, ANGULAR_VELOCITY),
    "m/s2": (1.0, ACCELERATION),
    "mm/s2": (1e-3, ACCELERATION),
    "deg/s2": (math.pi / 180.0, ANGULAR_ACCELERATION),
    "rad/s2": (1.0, ANGULAR_ACCELERATION),
    "N": (1.0, FORCE),
    "Nm": (1.0, TORQUE),
    "kg": (1.0, MASS),
    "%": (0.01, DIMENSIONLESS),
}

#: Unit names that are also predefined constants (`0.15*mps`, `2*mm`); `%` is not a name.
UNIT_CONSTANTS = {name: unit for name, unit in UNITS.items() if re.fullmatch(r"[A-Za-z]+", name)}


class DimensionError(ArithmeticError):
    """Two quantities of different dimensions were combined; the message names both."""


@dataclass(frozen=True, slots=True)
class Quantity:
    """A value in SI units with its dimension (dimensionless results collapse to plain floats)."""

    value: float          #: in SI units
    dim: Dimension

    def __str__(self) -> str:
        return f"{format_number(self.value)} {self.dim.symbol()}"


Number = float | int
Scalar = Number | Quantity


def quantity(value: float, dim: Dimension) -> Scalar:
    """A Quantity, or a plain float when the dimension cancelled out."""
    return float(value) if dim.is_dimensionless else Quantity(float(value), dim)


def parse_literal(text: str) -> Scalar:
    """`100mm/s` -> Quantity(0.1, velocity); `12` -> 12; `50%` -> 0.5. Raises KeyError for unknown units."""
    match = re.fullmatch(r"(\d+(?:\.\d*)?(?:[eE][+-]?\d+)?|\.\d+(?:[eE][+-]?\d+)?)(.*)", text)
    if match is None:
        raise ValueError(f"not a number: {text!r}")
    digits, unit = match.groups()
    number: Number = int(digits) if re.fullmatch(r"\d+", digits) else float(digits)
    if not unit:
        return number
    return to_si(number, unit)


#: Divisors for the units whose factor is a negative power of ten.
_DIVISORS = {1e-3: 1000.0, 1e-2: 100.0}


def to_si(number: Number, unit: str) -> Scalar:
    """`number` given in `unit`, as an SI quantity. Raises KeyError for an unknown unit."""
    factor, dim = UNITS[unit]
    divisor = _DIVISORS.get(factor)
    value = number / divisor if divisor else number * factor
    return quantity(value, dim)


def dim_of(value: object) -> Dimension:
    """The dimension of a number or quantity (anything else: dimensionless)."""
    return value.dim if isinstance(value, Quantity) else DIMENSIONLESS


def magnitude(value: Scalar) -> float:
    """The SI value of a number or quantity."""
    return value.value if isinstance(value, Quantity) else float(value)


def _plain_as(value: Scalar, other: Scalar) -> Dimension:
    """The dimension of `value`; a plain number meeting a quantity is in SI of the quantity's dimension."""
    if type(value) is not Quantity and type(other) is Quantity:
        return other.dim
    return dim_of(value)


def add(a: Scalar, b: Scalar, op: str = "+") -> Scalar:
    """a + b (or a - b) with both dimensions equal."""
    da, db = _plain_as(a, b), _plain_as(b, a)
    if da != db:
        raise DimensionError(f"cannot {'add' if op == '+' else 'subtract'} {da} ({da.symbol()}) and {db} ({db.symbol()})")
    if da.is_dimensionless:
        return a + b if op == "+" else a - b  # type: ignore[operator]
    va, vb = magnitude(a), magnitude(b)
    return Quantity(va + vb if op == "+" else va - vb, da)


def multiply(a: Scalar, b: Scalar) -> Scalar:
    """a * b; dimensions multiply."""
    if not isinstance(a, Quantity) and not isinstance(b, Quantity):
        return a * b
    return quantity(magnitude(a) * magnitude(b), dim_of(a) * dim_of(b))


def divide(a: Scalar, b: Scalar) -> Scalar:
    """a / b; dimensions divide. Division by zero raises ZeroDivisionError."""
    vb = magnitude(b)
    if vb == 0:
        raise ZeroDivisionError("division by zero")
    if not isinstance(a, Quantity) and not isinstance(b, Quantity):
        result = a / b
        return int(result) if isinstance(a, int) and isinstance(b, int) and result == int(result) else result
    return quantity(magnitude(a) / vb, dim_of(a) / dim_of(b))


def compare_dims(a: Scalar, b: Scalar) -> None:
    """Raise DimensionError unless a and b can be compared."""
    da, db = _plain_as(a, b), _plain_as(b, a)
    if da != db:
        raise DimensionError(f"cannot compare {da} ({da.symbol()}) with {db} ({db.symbol()})")


def format_number(value: float | int) -> str:
    """Shortest text that reads back as the same value, without a trailing `.0` (PRINT's rule)."""
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    if isinstance(value, int):
        return str(value)
    if math.isfinite(value) and value == int(value) and abs(value) < 1e16:
        return str(int(value))
    return repr(float(value))
