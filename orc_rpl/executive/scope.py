"""Static scopes of a program (docs/language.md section 8): which names are global, which are local to a routine."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field

from orc_rpl.syntax import nodes as n


@dataclass(frozen=True, slots=True)
class Scope:
    """Where an expression or statement is compiled: its routine's locals and its lexical FRAME block."""

    routine: str | None = None                  #: None: the main program
    locals: frozenset[str] = frozenset()        #: names local to the routine (parameters and first assignments)
    frame: str = "world"                        #: innermost enclosing FRAME block
    in_motion: bool = False                     #: evaluated inside the motion cycle (UNTIL, function parameters)

    def is_local(self, name: str) -> bool:
        return name in self.locals

    def with_frame(self, frame: str) -> Scope:
        return Scope(self.routine, self.locals, frame, self.in_motion)

    def for_motion(self) -> Scope:
        return Scope(self.routine, self.locals, self.frame, True)


def statements(body: n.Body, into_routines: bool = False) -> Iterator[n.Statement]:
    """Every statement of a block, nested blocks included (routine bodies only when asked)."""
    for stmt in body:
        yield stmt
        if isinstance(stmt, n.Routine) and not into_routines:
            continue
        yield from statements(nested_bodies(stmt), into_routines)


def nested_bodies(stmt: n.Statement) -> tuple[n.Statement, ...]:
    """The statements directly inside a compound statement, in source order (inline arm statements included)."""
    out: list[n.Statement] = []
    if isinstance(stmt, n.If):
        for branch in stmt.branches:
            out.extend(branch.body)
        out.extend(stmt.else_body or ())
    elif isinstance(stmt, (n.While, n.For, n.FrameBlock, n.Routine)):
        out.extend(stmt.body)
    elif isinstance(stmt, n.Case):
        for arm in (*stmt.arms, *((stmt.else_arm,) if stmt.else_arm else ())):
            if arm.inline is not None:
                out.append(arm.inline)
            out.extend(arm.body)
    elif isinstance(stmt, n.Try):
        out.extend(stmt.body)
        for handler in stmt.handlers:
            if handler.inline is not None:
                out.append(handler.inline)
            out.extend(handler.body)
    return tuple(out)


def assigned_names(body: n.Body) -> set[str]:
    """Names a block binds: declarations, assignments to a plain name, FOR variables, ENUM members, INSTALL names."""
    names: set[str] = set()
    for stmt in statements(body):
        if isinstance(stmt, n.Declaration):
            names.add(stmt.name.id)
        elif isinstance(stmt, n.Assign) and isinstance(stmt.target, n.Name):
            names.add(stmt.target.id)
        elif isinstance(stmt, n.For):
            names.add(stmt.variable.id)
        elif isinstance(stmt, n.EnumDecl):
            names.add(stmt.name.id)
            names.update(member.id for member in stmt.members)
        elif isinstance(stmt, n.Install):
            names.add(stmt.name.id)
    return names


@dataclass(slots=True)
class ProgramScopes:
    """The global names of a program and the local names of each routine."""

    globals: set[str] = field(default_factory=set)
    routines: dict[str, n.Routine] = field(default_factory=dict)
    locals: dict[str, frozenset[str]] = field(default_factory=dict)
    installed: set[str] = field(default_factory=set)

    def scope_of(self, routine: str | None) -> Scope:
        return Scope(routine, self.locals.get(routine, frozenset()) if routine else frozenset())


def analyse(program: n.Program) -> ProgramScopes:
    """Globals are the names bound at the top level; a routine's locals are its parameters, its own
    declarations, and names it assigns that are not global."""
    scopes = ProgramScopes()
    scopes.globals = assigned_names(program.body)
    for stmt in statements(program.body, into_routines=True):
        if isinstance(stmt, n.Install):
            scopes.installed.add(stmt.name.id)
        if isinstance(stmt, n.Routine):
            scopes.routines[stmt.name.id] = stmt
    for name, routine in scopes.routines.items():
        declared = {s.name.id for s in statements(routine.body) if isinstance(s, n.Declaration)}
        bound = assigned_names(routine.body) - scopes.globals
        scopes.locals[name] = frozenset({p.id for p in routine.params} | declared | bound)
    return scopes
