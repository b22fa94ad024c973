"""Rebuilding frozen trees: map the names that refer to things (positions, tools, frames) and leave every other field alone."""

from __future__ import annotations

import dataclasses
from typing import Callable, Iterator

from orc_rpl.syntax import nodes as n

#: Fields holding a Name that is not a reference to a position, tool or frame (declared names, fields, attributes).
_NOT_REFERENCES = frozenset({"name", "names", "params", "variable", "members", "kind", "labels"})

#: Called on each referring expression top down: a replacement, or None to look inside it.
ExprMap = Callable[[n.Expression], "n.Expression | None"]


def map_references(node: n.Node, fn: ExprMap) -> n.Node:
    """The node with `fn` applied to every expression that may refer to the world (spans are kept)."""
    if isinstance(node, n.Expression):
        replaced = fn(node)
        if replaced is not None:
            return replaced
    changes = {}
    for field in dataclasses.fields(node):  # type: ignore[arg-type]
        if field.name == "span":
            continue
        value = getattr(node, field.name)
        if field.name in _NOT_REFERENCES:
            continue
        if isinstance(value, n.Node):
            new = map_references(value, fn)
        elif isinstance(value, tuple) and value and isinstance(value[0], n.Node):
            new = tuple(map_references(item, fn) for item in value)
        else:
            continue
        if new is not value and new != value:
            changes[field.name] = new
    return dataclasses.replace(node, **changes) if changes else node  # type: ignore[type-var]


def map_body(body: n.Body, fn: ExprMap) -> n.Body:
    """Every statement of a body mapped."""
    return tuple(map_references(stmt, fn) for stmt in body)  # type: ignore[misc]


def references(node: n.Node) -> Iterator[n.Expression]:
    """Every expression that may refer to the world, outermost first (Field and Index included, then their parts)."""
    if isinstance(node, n.Expression):
        yield node
    for field in dataclasses.fields(node):  # type: ignore[arg-type]
        if field.name == "span" or field.name in _NOT_REFERENCES:
            continue
        value = getattr(node, field.name)
        if isinstance(value, n.Node):
            yield from references(value)
        elif isinstance(value, tuple):
            for item in value:
                if isinstance(item, n.Node):
                    yield from references(item)


def statements(body: n.Body) -> Iterator[n.Statement]:
    """Every statement of a body and of the blocks inside it (expressions are not visited)."""
    stack = list(reversed(body))
    while stack:
        stmt = stack.pop()
        yield stmt
        for child in reversed(list(stmt.children())):
            if isinstance(child, n.Statement):
                stack.append(child)
            elif isinstance(child, (n.Branch, n.CaseArm, n.Handler)):
                stack.extend(c for c in reversed(list(child.children())) if isinstance(c, n.Statement))


def declared_names(program: n.Program) -> set[str]:
    """Names the program itself declares or assigns: they shadow world objects (INSTALL may name a world tool: no shadow)."""
    out: set[str] = set()
    for node in statements(program.body):
        if isinstance(node, n.Declaration):
            out.add(node.name.id)
        elif isinstance(node, n.EnumDecl):
            out |= {node.name.id, *(m.id for m in node.members)}
        elif isinstance(node, n.Routine):
            out |= {node.name.id, *(p.id for p in node.params)}
        elif isinstance(node, n.For):
            out.add(node.variable.id)
        elif isinstance(node, n.Assign) and isinstance(node.target, n.Name):
            out.add(node.target.id)
    return out
