"""A thin adapter over the executive for the pendant: statements in a lexical context, step by step; pointer to any statement."""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator

from orc_rpl.executive.executive import Executive
from orc_rpl.executive.scope import Scope
from orc_rpl.executive.signals import RunError
from orc_rpl.pendant.tree import EditError, Stop, child_bodies
from orc_rpl.syntax import nodes as n

#: Statements that give names their values; the pendant runs them first so any statement can run on its own.
DECLARATIONS = (n.Declaration, n.EnumDecl, n.Install)


def statement_steps(ex: Executive, stmt: n.Statement, routine: str | None, frame: str,
                    settle: bool = True) -> Iterator[object]:
    """Run one statement in a lexical context, yielding once per motion cycle so the screen can show and stop it."""
    return ex.statement_steps(stmt, routine, frame, settle)


def declarations(program: n.Program) -> Iterator[tuple[n.Statement, str]]:
    """Every declaration outside routines, in program order, with the FRAME block it stands in."""

    def visit(body: n.Body, frame: str) -> Iterator[tuple[n.Statement, str]]:
        for stmt in body:
            if isinstance(stmt, DECLARATIONS):
                yield stmt, frame
            elif not isinstance(stmt, n.Routine):
                inner = stmt.frame.id if isinstance(stmt, n.FrameBlock) else frame
                for _, child in child_bodies(stmt):
                    yield from visit(child, inner)

    yield from visit(program.body, "world")


def prepare(ex: Executive, program: n.Program) -> list[RunError]:
    """Give every declared name its value (frames, positions, tools, installed equipment) without moving the robot,
    so that a statement executed on its own finds the names it uses. Returns the declarations that failed."""
    failures = []
    for stmt, frame in declarations(program):
        try:
            for _ in statement_steps(ex, stmt, None, frame, settle=False):  # a jog may be running: leave it
                pass
        except RunError as error:
            failures.append(error)
    return failures


def tail(program: n.Program, stop: Stop) -> n.Body:
    """The statements that run when execution starts at a cursor stop: the rest of its body, inside the blocks that
    give it its context (FRAME, TRY), then the rest of every enclosing body. A WHILE is tested again after the
    rest of its body; IF, CASE and FOR continue after their END line. Original nodes keep their lines."""
    if stop.routine is not None:
        raise EditError("the program pointer cannot be set inside a PROC or FUNC: set it at a call of it")
    index = stop.index + 1 if stop.end else stop.index

    def build(body: n.Body, path: tuple, index: int) -> n.Body:
        if not path:
            return body[index:]
        (i, key), rest = path[0], path[1:]
        stmt = body[i]
        inner = build(dict(child_bodies(stmt))[key], rest, index)
        after = body[i + 1:]
        if isinstance(stmt, n.FrameBlock):
            return (dataclasses.replace(stmt, body=inner),) + after
        if isinstance(stmt, n.Try) and key == ("body", None):
            return (dataclasses.replace(stmt, body=inner),) + after
        if isinstance(stmt, n.While):
            return inner + (stmt,) + after
        return inner + after

    return build(program.body, stop.body, index)


def point_at(ex: Executive, program: n.Program, stop: Stop) -> str:
    """Set the program pointer to a cursor stop: the executive's main block becomes the tail from there (names keep
    their values). Returns the executive's status: "paused" before the statement, or "finished" at the end."""
    ex.main = ex.compiler.block(tail(program, stop), Scope())
    # Executive has no public "set pointer": a fresh generator over the new main block is the same thing.
    ex._gen = None
    ex.status, ex.error, ex.pointer = "ready", None, None
    status = ex.step_into()
    # the FRAME and TRY wrappers of the tail are entered, so the pointer shows the statement itself
    while status == "paused" and isinstance(ex.pointer.statement, (n.FrameBlock, n.Try)) and ex.pointer.line != stop.line \
            and not stop.end:
        status = ex.step_into()
    return status
