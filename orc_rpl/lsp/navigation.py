"""Go to definition and the document outline (routines, frames, positions, ...), in 1-based spans the server converts."""

from __future__ import annotations

from dataclasses import dataclass

from lsprotocol import types as T

from orc_rpl.lsp.analysis import Analysis
from orc_rpl.lsp.index import Definition, ProgramIndex, name_at
from orc_rpl.syntax import nodes as n


@dataclass(frozen=True, slots=True)
class Place:
    """A place to jump to: a file and a 1-based span (the end exclusive; 0 for one character)."""

    path: str
    span: n.Span


def definition_of(analysis: Analysis, index: ProgramIndex, line: int, column: int) -> Place | None:
    """Where the name at the 1-based (line, column) is declared: in the program, or in the world file of an off-line program."""
    if analysis.program is None:
        return None
    target = name_at(analysis.program, line, column)
    if target is None:
        return None
    owner = target.owner
    if owner is None:
        found = index.lookup(target.name.id, line)
        if found is not None:
            return Place(analysis.path, found.span)
    world = analysis.world
    if world is None:
        return None
    names = {o.name for o in world.objects}
    if owner is None and target.name.id in names:
        location = world.object(target.name.id).location
    elif owner is not None and owner.id in names:
        obj = world.object(owner.id)
        entry = obj.frame(target.name.id) or obj.path(target.name.id)
        if entry is None:
            return None
        location = entry.location
    else:
        return None
    if location.line == 0 or location.path.startswith("<"):
        return None
    return Place(location.path, n.Span(location.line, location.column, location.end_line, location.end_column))


#: The outline's symbol kind of each definition kind.
_SYMBOL = {
    "proc": T.SymbolKind.Function, "func": T.SymbolKind.Function, "frame": T.SymbolKind.Namespace,
    "position": T.SymbolKind.Constant, "path": T.SymbolKind.Array, "tool": T.SymbolKind.Object,
    "installed": T.SymbolKind.Object, "constant": T.SymbolKind.Constant, "variable": T.SymbolKind.Variable,
    "enum": T.SymbolKind.Enum, "enum value": T.SymbolKind.EnumMember,
}


@dataclass(frozen=True, slots=True)
class Outline:
    """One entry of the document outline: a declaration and the declarations inside it (a routine's)."""

    definition: Definition
    children: tuple[Outline, ...] = ()

    @property
    def symbol_kind(self) -> T.SymbolKind:
        return _SYMBOL.get(self.definition.kind, T.SymbolKind.Variable)


def outline(index: ProgramIndex) -> list[Outline]:
    """Top-level declarations in file order; a routine holds its parameters' and locals' declarations."""
    out = []
    for definition in sorted(index.globals.values(), key=lambda d: (d.span.line, d.span.column)):
        if definition.kind == "enum value":
            continue
        if isinstance(definition.statement, n.Routine):
            inner = index.locals.get(id(definition.statement), {}).values()
            children = tuple(Outline(d) for d in sorted(inner, key=lambda d: (d.span.line, d.span.column))
                             if d.kind not in ("parameter", "local"))
            out.append(Outline(definition, children))
        else:
            out.append(Outline(definition))
    return out
