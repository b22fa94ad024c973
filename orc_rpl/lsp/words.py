"""How the language server names the registry's words: attribute types with their units, defaults, keyword spellings."""

from __future__ import annotations

import re

from orc_rpl.application.declarations import AttributeSpec, ValueType, describe_type
from orc_rpl.syntax.lexicon import RESERVED
from orc_rpl.syntax.offline_builder import OFFLINE_KEYWORDS
from orc_rpl.syntax.units import DIMENSIONLESS, Dimension, Quantity, format_number

#: A motion keyword as the first word of a line: `GRINDMOVE` on-line, `grindmove` or `moveto` off-line.
ONLINE_MOTION = re.compile(r"^\s*((?:[A-Z][A-Z0-9_]*)?MOVE)\b")
OFFLINE_MOTION = re.compile(r"^\s*((?:[a-z][a-z0-9_]*)?move(?:to)?)\b")


def registry_keyword(word: str) -> str:
    """The registry's spelling of a motion keyword as written in either syntax (`moveto` is MOVE)."""
    return "MOVE" if word == "moveto" else word.upper()


def type_with_unit(value_type: ValueType) -> str:
    """`a velocity (m/s)`, `a number`, `a pose`: how completion and hover name a value type."""
    words = describe_type(value_type)
    if isinstance(value_type, Dimension) and value_type != DIMENSIONLESS:
        return f"{words} ({value_type.symbol()})"
    return words


def default_text(spec: AttributeSpec) -> str:
    """A declared default as a person reads it: `30 N` (a plain number is in the SI unit of the first quantity type), `FINE`."""
    value = spec.default
    if isinstance(value, Quantity):
        return f"{format_number(value.value)} {value.dim.symbol()}"
    if isinstance(value, float | int) and not isinstance(value, bool):
        unit = next((t.symbol() for t in spec.types if isinstance(t, Dimension) and t != DIMENSIONLESS), "")
        return format_number(value) + (f" {unit}" if unit else "")
    return str(value)


def attribute_detail(spec: AttributeSpec) -> str:
    """One line: `a velocity (m/s) or a number; default 30 N; also V, VELOCITY`."""
    text = " or ".join(type_with_unit(t) for t in spec.types)
    if spec.default is not None:
        text += f"; default {default_text(spec)}"
    if spec.aliases:
        text += "; also " + ", ".join(spec.aliases)
    return text


def keywords(offline: bool) -> list[str]:
    """The reserved words of a syntax, sorted (motion keywords come from the registry)."""
    return sorted(OFFLINE_KEYWORDS if offline else RESERVED)
