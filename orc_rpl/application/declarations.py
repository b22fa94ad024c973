"""What an application feature declares: motion keywords, their attributes, functions and INSTALL kinds."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable

from orc_rpl.syntax.units import DIMENSION_NAMES, Dimension

#: A value type an attribute or argument accepts: a Dimension for numbers and quantities,
#: or one of these tags.
TYPE_TAGS = frozenset({"pose", "joints", "position", "path", "string", "bool", "list", "tuning", "zone", "any", "function"})
ValueType = Dimension | str


def describe_type(value_type: ValueType) -> str:
    """A type as messages name it: `a velocity`, `a pose`, `a SpotGun`."""
    if isinstance(value_type, Dimension):
        word = DIMENSION_NAMES.get(value_type, value_type.symbol())
        return f"{'an' if word[0] in 'aeiou' else 'a'} {word}" if word != "number" else "a number"
    if value_type.startswith("installed:"):
        return f"an installed {value_type.split(':', 1)[1]}"
    article = "an" if value_type[0] in "aeiou" else "a"
    return {"zone": "a zone (length or FINE)", "position": "a position (pose or joints)"}.get(value_type, f"{article} {value_type}")


def describe_types(types: tuple[ValueType, ...]) -> str:
    """`a velocity or a number`."""
    words = [describe_type(t) for t in types]
    return words[0] if len(words) == 1 else ", ".join(words[:-1]) + " or " + words[-1]


@dataclass(frozen=True, slots=True)
class AttributeSpec:
    """One `WITH NAME = value` attribute a motion or INSTALL kind accepts."""

    name: str                                  #: upper case as written (SPEED, FORCE)
    types: tuple[ValueType, ...]               #: accepted value types
    default: Any = None                        #: value when the attribute is absent (None: no default)
    doc: str = ""                              #: one line for `:help` and the docs
    aliases: tuple[str, ...] = ()              #: other spellings (V, VELOCITY for SPEED)
    function_ok: bool = True                   #: a FUNC name may be given (a function of s or t)
    literal_check: Callable[[str], str | None] | None = None  #: why a string literal is refused (PORT), or None

    @property
    def names(self) -> tuple[str, ...]:
        return (self.name, *self.aliases)


@dataclass(frozen=True, slots=True)
class MotionSpec:
    """A motion keyword (`GRINDMOVE`) with its attributes and what it needs."""

    keyword: str
    doc: str
    attributes: tuple[AttributeSpec, ...]
    targets: tuple[str, ...] = ("TO",)         #: which of TO / ALONG it accepts
    needs_via: bool = False                    #: CMOVE needs its auxiliary point
    requires: tuple[str, ...] = ()             #: INSTALL kinds the tool must carry (WELDMOVE: SpotGun)
    output_functions: tuple[str, ...] = ()     #: `WITH Id = IDENT(...)` binds Id (IDENTMOVE)
    origin: str = ""                           #: feature module that declared it
    execute: Callable[..., Any] | None = field(default=None, compare=False)  #: behaviour, set by the feature

    def attribute(self, name: str) -> AttributeSpec | None:
        """The attribute called `name` (or one of its aliases)."""
        for spec in self.attributes:
            if name in spec.names:
                return spec
        return None

    @property
    def attribute_names(self) -> tuple[str, ...]:
        return tuple(name for spec in self.attributes for name in spec.names)


@dataclass(frozen=True, slots=True)
class ParamSpec:
    """One parameter of an application function."""

    name: str
    types: tuple[ValueType, ...] = ("any",)
    default: Any = None
    required: bool = True


@dataclass(frozen=True, slots=True)
class FunctionSpec:
    """A function the language can call (`POSE`, `SQRT`, `RecordSeam`, `IDENT`)."""

    name: str
    doc: str
    params: tuple[ParamSpec, ...]
    returns: ValueType = "any"
    variadic: bool = False                     #: MIN/MAX take any number (at least min_args)
    moves: bool = False                        #: calling it moves the robot (RecordSeam, CALIBRATE)
    of_arguments: bool = False                 #: its value depends on its arguments alone (POSE, SQRT; not IDENT,
                                               #: which reads the last recording), so a motion computed early may call it
    origin: str = ""
    implementation: Callable[..., Any] | None = field(default=None, compare=False)

    @property
    def min_args(self) -> int:
        return sum(1 for p in self.params if p.required)

    @property
    def max_args(self) -> int | None:
        return None if self.variadic else len(self.params)

    @property
    def pure(self) -> bool:
        """Free of side effects, so a parameter function may call it: every function that does not move the robot."""
        return not self.moves


@dataclass(frozen=True, slots=True)
class MethodSpec:
    """A method or sensor value of an installed object (`Gripper1.Close`, `LaserSensor.Distance`)."""

    name: str
    doc: str
    returns: ValueType | None = None           #: None: a command; otherwise a readable value
    arity: int = 0


@dataclass(frozen=True, slots=True)
class InstallKindSpec:
    """An `INSTALL name AS Kind` kind: equipment or a sensor."""

    name: str
    doc: str
    attributes: tuple[AttributeSpec, ...]
    methods: tuple[MethodSpec, ...] = ()
    is_sensor: bool = False
    origin: str = ""
    factory: Callable[..., Any] | None = field(default=None, compare=False)

    def attribute(self, name: str) -> AttributeSpec | None:
        return next((a for a in self.attributes if name in a.names), None)

    def method(self, name: str) -> MethodSpec | None:
        return next((m for m in self.methods if m.name == name), None)
