"""Names a program can see: static types, symbols, scopes, and the collection of a scope's declarations."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from typing import Iterator

from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.lexicon import PREDEFINED_NAMES
from orc_rpl.syntax.units import UNIT_CONSTANTS, Dimension

WORLD = "world"


@dataclass(frozen=True, slots=True)
class StaticType:
    """What the checker knows about a value; `any` means it cannot tell."""

    kind: str                          #: number, pose, joints, path, bool, string, list, tool, frame, zone,
                                       #: installed, enum, routine, io, robot, any
    dim: Dimension | None = None       #: for numbers
    frame: str | None = None           #: for poses and paths: the frame they are relative to, if known
    detail: str | None = None          #: installed kind, enum name, routine kind (PROC/FUNC)

    def __str__(self) -> str:
        if self.kind == "number" and self.dim is not None:
            from orc_rpl.application.declarations import describe_type

            return describe_type(self.dim)
        return {"installed": f"an installed {self.detail}"}.get(self.kind, f"a {self.kind}")


ANY = StaticType("any")
BOOL = StaticType("bool")
STRING = StaticType("string")


@lru_cache(maxsize=None)
def number(dim: Dimension) -> StaticType:
    """A number or quantity of dimension `dim`."""
    return StaticType("number", dim)


@dataclass(slots=True)
class Symbol:
    """A declared or assigned name."""

    name: str
    kind: str                          #: var, const, pos, path, tool, frame, enum, enum_value, install, proc,
                                       #: func, param, loop, binding, predefined, unit, function
    type: StaticType = ANY
    node: n.Node | None = None         #: where it was declared (None for built-ins)
    params: int | None = None          #: routines: number of parameters


@dataclass
class Scope:
    """One level of names: built-ins, the program's globals, or one routine's locals."""

    parent: Scope | None = None
    symbols: dict[str, Symbol] = field(default_factory=dict)
    routine: n.Routine | None = None

    def lookup(self, name: str) -> Symbol | None:
        scope: Scope | None = self
        while scope is not None:
            found = scope.symbols.get(name)
            if found is not None:
                return found
            scope = scope.parent
        return None

    def visible_names(self) -> Iterator[str]:
        scope: Scope | None = self
        while scope is not None:
            yield from scope.symbols
            scope = scope.parent


def builtin_scope(function_names: list[str]) -> Scope:
    """Predefined names, unit constants and the registry's functions."""
    from orc_rpl.syntax.units import quantity

    scope = Scope()
    types = {
        "ARM": StaticType("tool"),
        "ROBOT": StaticType("robot"),
        "HERE": StaticType("pose"),
        "world": StaticType("frame", frame=WORLD),
        "FINE": StaticType("zone"),
    }
    for name in PREDEFINED_NAMES:
        scope.symbols[name] = Symbol(name, "predefined", types.get(name, StaticType("io")))
    for name, (factor, dim) in UNIT_CONSTANTS.items():
        value = quantity(factor, dim)
        scope.symbols[name] = Symbol(name, "unit", number(dim) if not isinstance(value, float) else number(Dimension()))
    for name in function_names:
        scope.symbols[name] = Symbol(name, "function", ANY)
    return scope


def assigned_names(body: n.Body) -> Iterator[tuple[str, n.Node]]:
    """Names first assigned by statements of a body (not descending into routines)."""
    for stmt in body:
        if isinstance(stmt, n.Assign) and isinstance(stmt.target, n.Name):
            yield stmt.target.id, stmt.target
        elif isinstance(stmt, n.For):
            yield stmt.variable.id, stmt.variable
        elif isinstance(stmt, n.Motion):
            for clause in stmt.clauses:
                if isinstance(clause, n.With) and isinstance(clause.value, n.Call) and isinstance(clause.value.function, n.Name):
                    if clause.value.function.id == "IDENT":
                        yield clause.name.id, clause.name
        for inner in nested_bodies(stmt):
            yield from assigned_names(inner)


def nested_bodies(stmt: n.Statement) -> Iterator[n.Body]:
    """The blocks directly inside a compound statement (routines excluded: they are their own scope)."""
    if isinstance(stmt, n.If):
        for branch in stmt.branches:
            yield branch.body
        if stmt.else_body is not None:
            yield stmt.else_body
    elif isinstance(stmt, (n.While, n.For, n.FrameBlock)):
        yield stmt.body
    elif isinstance(stmt, n.Case):
        yield stmt.leading
        for arm in (*stmt.arms, *([stmt.else_arm] if stmt.else_arm else [])):
            yield tuple(s for s in (arm.inline,) if s is not None) + arm.body
    elif isinstance(stmt, n.Try):
        yield stmt.body
        for handler in stmt.handlers:
            yield tuple(s for s in (handler.inline,) if s is not None) + handler.body


def declarations(body: n.Body) -> Iterator[n.Statement]:
    """Declaration statements of a body at any block depth (not inside routines)."""
    for stmt in body:
        if isinstance(stmt, (n.Declaration, n.EnumDecl, n.Install, n.Routine)):
            yield stmt
        for inner in nested_bodies(stmt):
            yield from declarations(inner)
