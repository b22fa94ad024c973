"""`orc run --set NAME=VALUE`: a program with some of its top-level CONST values replaced (for sweeps over a parameter)."""

from __future__ import annotations

import dataclasses
from typing import Sequence

from orc_rpl.errors import SourceError, UsageError
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.parser import parse


def parse_setting(text: str) -> tuple[str, str]:
    """`Vmax=1.2mps` -> ("Vmax", "1.2mps"); a UsageError naming --set otherwise."""
    name, equals, value = text.partition("=")
    if not equals or not name.strip() or not value.strip():
        raise UsageError(f"--set: expected NAME=VALUE, e.g. Vmax=1.2mps, got {text!r}")
    return name.strip(), value.strip()


def _value_expression(name: str, value: str) -> n.Expression:
    """The expression of `value`, parsed as the on-line syntax parses a CONST's value."""
    try:
        program = parse(f"CONST {name} = {value}\n", "--set")
    except SourceError:
        raise UsageError(f"--set {name}={value}: {value!r} is not a value of the language (e.g. 3, 1.2mps, 150mm)") from None
    statements = [s for s in program.body if isinstance(s, n.Declaration)]
    if len(statements) != 1:
        raise UsageError(f"--set {name}={value}: {value!r} is not a single value")
    return statements[0].value


def _with_span(node: n.Node, span: n.Span) -> n.Node:
    """The node and its children, all placed at `span` (a checker's message then points at the declaration)."""
    changes: dict[str, object] = {}
    for field in dataclasses.fields(node):  # type: ignore[arg-type]
        value = getattr(node, field.name)
        if field.name == "span":
            changes["span"] = span
        elif isinstance(value, n.Node):
            changes[field.name] = _with_span(value, span)
        elif isinstance(value, tuple) and value and isinstance(value[0], n.Node):
            changes[field.name] = tuple(_with_span(item, span) for item in value)
    return dataclasses.replace(node, **changes)  # type: ignore[type-var]


def override_constants(program: n.Program, settings: Sequence[str]) -> n.Program:
    """The program with each `NAME=VALUE` of `settings` replacing the value of its top-level `CONST NAME`.

    Only top-level CONSTs can be set: they are the program's parameters. An unknown name is a UsageError
    listing the CONSTs there are, so a misspelt sweep stops before anything runs.
    """
    if not settings:
        return program
    consts = {s.name.id: s for s in program.body if isinstance(s, n.Declaration) and s.kind == "CONST"}
    replaced: dict[str, n.Expression] = {}
    for text in settings:
        name, value = parse_setting(text)
        if name not in consts:
            known = ", ".join(sorted(consts)) or "none"
            raise UsageError(f"--set {name}={value}: the program has no top-level CONST {name!r} (its CONSTs: {known})")
        if name in replaced:
            raise UsageError(f"--set: {name} is set twice")
        replaced[name] = _value_expression(name, value)
    body = tuple(dataclasses.replace(s, value=_with_span(replaced[s.name.id], s.value.span))
                 if isinstance(s, n.Declaration) and s.kind == "CONST" and s.name.id in replaced else s
                 for s in program.body)
    return dataclasses.replace(program, body=body)
