"""The names of one program for an editor: where each is declared, which routine it belongs to, and the name under a cursor."""

from __future__ import annotations

from dataclasses import dataclass

from orc_rpl.checking.symbols import assigned_names, declarations
from orc_rpl.syntax import nodes as n

#: The kind a declaration statement gives its name.
_DECLARED = {"TOOL": "tool", "FRAME": "frame", "POS": "position", "PATH": "path", "CONST": "constant", "VAR": "variable"}


@dataclass(frozen=True, slots=True)
class Definition:
    """A name the program declares: its kind, the statement that declares it and the span of the name there."""

    name: str
    kind: str                         #: tool, frame, position, path, constant, variable, enum, enum value,
                                      #: installed, proc, func, parameter, local
    statement: n.Node                 #: the declaring statement (the Name itself for parameters and locals)
    span: n.Span                      #: where the name is written in its declaration
    routine: n.Routine | None = None  #: the routine it is local to, None for a global


def contains(span: n.Span, line: int, column: int) -> bool:
    """True when the 1-based (line, column) lies in the span (the end column is exclusive, but a cursor right after a word counts)."""
    if span.line == 0:
        return False
    end_line = span.end_line or span.line
    if not span.line <= line <= end_line:
        return False
    if line == span.line and column < span.column:
        return False
    return not (line == end_line and span.end_column and column > span.end_column)


def _declared(body: n.Body, routine: n.Routine | None) -> list[Definition]:
    out: list[Definition] = []
    for stmt in declarations(body):
        if isinstance(stmt, n.Routine):
            out.append(Definition(stmt.name.id, stmt.kind.lower(), stmt, stmt.name.span, routine))
        elif isinstance(stmt, n.EnumDecl):
            out.append(Definition(stmt.name.id, "enum", stmt, stmt.name.span, routine))
            out += [Definition(m.id, "enum value", stmt, m.span, routine) for m in stmt.members]
        elif isinstance(stmt, n.Install):
            out.append(Definition(stmt.name.id, "installed", stmt, stmt.name.span, routine))
        elif isinstance(stmt, n.Declaration):
            out.append(Definition(stmt.name.id, _DECLARED[stmt.kind], stmt, stmt.name.span, routine))
    return out


class ProgramIndex:
    """Every declared name of a program, globals first, then each routine's parameters and locals."""

    def __init__(self, program: n.Program) -> None:
        self.program = program
        self.globals: dict[str, Definition] = {}
        self.locals: dict[int, dict[str, Definition]] = {}   #: id(routine) -> its names
        self.routines: list[n.Routine] = []
        for definition in _declared(program.body, None):
            self.globals.setdefault(definition.name, definition)
        for name, node in assigned_names(program.body):
            self.globals.setdefault(name, Definition(name, "variable", node, node.span))
        for definition in self.globals.values():
            if isinstance(definition.statement, n.Routine):
                self._index_routine(definition.statement)

    def _index_routine(self, routine: n.Routine) -> None:
        self.routines.append(routine)
        names: dict[str, Definition] = {}
        for param in routine.params:
            names.setdefault(param.id, Definition(param.id, "parameter", param, param.span, routine))
        for definition in _declared(routine.body, routine):
            names.setdefault(definition.name, definition)
        for name, node in assigned_names(routine.body):
            if name not in self.globals:  # an assignment to a global updates the global
                names.setdefault(name, Definition(name, "local", node, node.span, routine))
        self.locals[id(routine)] = names

    def routine_at(self, line: int) -> n.Routine | None:
        """The routine whose text holds this 1-based line, if any."""
        return next((r for r in self.routines if r.span.line <= line <= (r.span.end_line or r.span.line)), None)

    def visible(self, line: int) -> dict[str, Definition]:
        """The names a statement on this line can use: the routine's own first, then the globals."""
        routine = self.routine_at(line)
        return {**self.globals, **(self.locals.get(id(routine), {}) if routine is not None else {})}

    def lookup(self, name: str, line: int) -> Definition | None:
        return self.visible(line).get(name)

    def definitions(self) -> list[Definition]:
        """Every definition, in file order (for document symbols)."""
        out = list(self.globals.values())
        for names in self.locals.values():
            out += names.values()
        return sorted(out, key=lambda d: (d.span.line, d.span.column))


@dataclass(frozen=True, slots=True)
class Target:
    """The name under a cursor and the node it is written in (a Field, a With, a Motion, a declaration...)."""

    name: n.Name
    parent: n.Node

    @property
    def owner(self) -> n.Name | None:
        """`base_plate` when the cursor is on `pos1` of `base_plate.pos1`."""
        parent = self.parent
        if isinstance(parent, n.Field) and parent.name is self.name and isinstance(parent.value, n.Name):
            return parent.value
        return None


def name_at(program: n.Program, line: int, column: int) -> Target | None:
    """The name written at the 1-based (line, column), with the node it is part of."""
    stack: list[n.Node] = [program]
    while stack:
        node = stack.pop()
        for child in node.children():
            if isinstance(child, n.Name) and contains(child.span, line, column):
                return Target(child, node)
            stack.append(child)
    return None
