"""Structured editing on the frozen syntax tree: cursor stops, and insert/delete/replace/wrap/shift of statements."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from orc_rpl.errors import OrcError, SourceError
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.parser import parse
from orc_rpl.syntax.printer import print_program

#: Where a body sits inside a compound statement: an attribute name, and an element index for tuples of arms.
BodyKey = tuple[str, int | None]
#: A body inside the program: for each level, the statement's index in the enclosing body and the body key.
BodyPath = tuple[tuple[int, BodyKey], ...]


class EditError(OrcError):
    """An edit that would break the program, or that the cursor cannot take; the program is left unchanged."""


@dataclass(frozen=True, slots=True)
class Stop:
    """A cursor stop: one statement (its first line) or the end line of a block statement."""

    body: BodyPath                    #: the body holding the statement
    index: int                        #: its index in that body
    statement: n.Statement
    line: int                         #: the line shown highlighted (1-based)
    end: bool = False                 #: True for the ENDFRAME/ENDIF/... line of a block
    frame: str = "world"              #: the FRAME block the statement is lexically in
    routine: str | None = None        #: the PROC/FUNC it is in (None: the main program)


def child_bodies(stmt: n.Statement) -> list[tuple[BodyKey, n.Body]]:
    """The bodies directly inside a compound statement, in source order."""
    if isinstance(stmt, (n.FrameBlock, n.While, n.For, n.Routine)):
        return [(("body", None), stmt.body)]
    if isinstance(stmt, n.If):
        out: list[tuple[BodyKey, n.Body]] = [(("branches", i), b.body) for i, b in enumerate(stmt.branches)]
        if stmt.else_body is not None:
            out.append((("else_body", None), stmt.else_body))
        return out
    if isinstance(stmt, n.Case):
        out = [(("leading", None), stmt.leading)] + [(("arms", i), a.body) for i, a in enumerate(stmt.arms)]
        if stmt.else_arm is not None:
            out.append((("else_arm", None), stmt.else_arm.body))
        return out
    if isinstance(stmt, n.Try):
        return [(("body", None), stmt.body)] + [(("handlers", i), h.body) for i, h in enumerate(stmt.handlers)]
    return []


def is_block(stmt: n.Statement) -> bool:
    """A statement written over several lines with an END... line."""
    return bool(child_bodies(stmt))


def _with_body(stmt: n.Statement, key: BodyKey, body: n.Body) -> n.Statement:
    attr, index = key
    if attr in ("branches", "arms", "handlers"):
        items = list(getattr(stmt, attr))
        items[index] = dataclasses.replace(items[index], body=body)  # type: ignore[index]
        return dataclasses.replace(stmt, **{attr: tuple(items)})  # type: ignore[arg-type]
    if attr == "else_arm":
        return dataclasses.replace(stmt, else_arm=dataclasses.replace(stmt.else_arm, body=body))  # type: ignore[attr-defined]
    return dataclasses.replace(stmt, **{attr: body})  # type: ignore[arg-type]


def _body_of(stmt: n.Statement, key: BodyKey) -> n.Body:
    return dict(child_bodies(stmt))[key]


def body_at(program: n.Program, path: BodyPath) -> n.Body:
    """The statements of the body at `path`."""
    body = program.body
    for index, key in path:
        body = _body_of(body[index], key)
    return body


def replace_body(program: n.Program, path: BodyPath, new_body: n.Body) -> n.Program:
    """A new program with the body at `path` replaced (the frozen nodes above it rebuilt)."""

    def rebuild(body: n.Body, rest: BodyPath) -> n.Body:
        if not rest:
            return new_body
        (index, key), tail = rest[0], rest[1:]
        stmt = body[index]
        inner = rebuild(_body_of(stmt, key), tail)
        return body[:index] + (_with_body(stmt, key, inner),) + body[index + 1:]

    return n.Program(rebuild(program.body, path))


def stops(program: n.Program) -> list[Stop]:
    """Every cursor stop in document order: each statement's first line, and each block's END line."""
    out: list[Stop] = []

    def visit(body: n.Body, path: BodyPath, frame: str, routine: str | None) -> None:
        for i, stmt in enumerate(body):
            out.append(Stop(path, i, stmt, stmt.span.line, False, frame, routine))
            if not is_block(stmt):
                continue
            inner_frame = stmt.frame.id if isinstance(stmt, n.FrameBlock) else ("world" if isinstance(stmt, n.Routine) else frame)
            inner_routine = stmt.name.id if isinstance(stmt, n.Routine) else routine
            for key, child in child_bodies(stmt):
                visit(child, path + ((i, key),), inner_frame, inner_routine)
            out.append(Stop(path, i, stmt, stmt.span.end_line or stmt.span.line, True, frame, routine))

    visit(program.body, (), "world", None)
    return out


def reparse(program: n.Program, path: str = "<pendant>") -> tuple[str, n.Program]:
    """Print an edited tree canonically and parse it back, so spans are fresh and the text is known to be valid."""
    text = print_program(program)
    try:
        return text, parse(text, path)
    except SourceError as error:  # the printer and parser disagree: refuse the edit rather than keep bad text
        raise EditError("the edit would leave the program unparsable:\n" + error.format()) from None


def insert_at(program: n.Program, stop: Stop, statements: n.Body) -> tuple[n.Program, BodyPath, int]:
    """Insert after the cursor's statement in its block; on a block's first line, as the first statements inside.

    Returns the new program and where the first inserted statement is.
    """
    stmt = stop.statement
    if not stop.end and is_block(stmt):
        key = child_bodies(stmt)[0][0]
        if isinstance(stmt, n.Case):  # the leading comments of a CASE hold no statements
            key = (("arms", 0) if stmt.arms else ("leading", None))
        path = stop.body + ((stop.index, key),)
        body = body_at(program, path)
        return replace_body(program, path, tuple(statements) + body), path, 0
    body = body_at(program, stop.body)
    new = body[:stop.index + 1] + tuple(statements) + body[stop.index + 1:]
    return replace_body(program, stop.body, new), stop.body, stop.index + 1


def delete_range(program: n.Program, path: BodyPath, first: int, last: int) -> n.Program:
    """Remove statements first..last (inclusive) of one body."""
    body = body_at(program, path)
    return replace_body(program, path, body[:first] + body[last + 1:])


def replace_at(program: n.Program, path: BodyPath, index: int, statement: n.Statement) -> n.Program:
    """Put `statement` in place of the statement at `index` of a body."""
    body = body_at(program, path)
    return replace_body(program, path, body[:index] + (statement,) + body[index + 1:])


def wrap_frame(program: n.Program, path: BodyPath, first: int, last: int, frame: str) -> n.Program:
    """Wrap statements first..last of one body in `FRAME frame ... ENDFRAME`."""
    body = body_at(program, path)
    block = n.FrameBlock(n.Name(frame), tuple(body[first:last + 1]))
    return replace_body(program, path, body[:first] + (block,) + body[last + 1:])


def shift(program: n.Program, path: BodyPath, first: int, last: int, offset: int) -> n.Program:
    """Move statements first..last of one body up (offset -1) or down (+1) past their neighbour."""
    body = list(body_at(program, path))
    if offset < 0 and first == 0 or offset > 0 and last == len(body) - 1:
        raise EditError("the statements are already at the " + ("top" if offset < 0 else "bottom") + " of their block")
    chunk = body[first:last + 1]
    del body[first:last + 1]
    body[first + offset:first + offset] = chunk
    return replace_body(program, path, tuple(body))
