"""FRAME blocks (thesis 7.3): inserted around the statements that use an on-line frame's positions, nested as the frames nest; removed again."""

from __future__ import annotations

import dataclasses
from typing import Mapping

from orc_rpl.syntax import nodes as n
from orc_rpl.transform.job import Job
from orc_rpl.transform.treemap import references

Chain = tuple[str, ...]
#: How a statement relates to the frame blocks around it.
NEUTRAL, HERE, MIXED = "", "\0here", "\0mixed"


def _chains(stmt: n.Statement, chains: Mapping[str, Chain]) -> set[Chain]:
    """The FRAME nestings of every position a statement refers to, outside the FRAME blocks it already holds
    (declarations refer to none: they stay on top)."""
    if isinstance(stmt, (n.Declaration, n.Comment, n.Blank, n.Routine, n.FrameBlock)):
        return set()
    found: set[Chain] = set()
    stack: list[n.Node] = [stmt]
    while stack:
        node = stack.pop()
        for child in references_here(node):
            if isinstance(child, n.Name) and child.id in chains:
                found.add(chains[child.id])
        stack.extend(c for c in node.children() if isinstance(c, n.Statement) and not isinstance(c, n.FrameBlock)
                     or isinstance(c, (n.Branch, n.CaseArm, n.Handler)))
    return found


def references_here(node: n.Node):  # type: ignore[no-untyped-def]
    """The referring expressions of one statement or arm, not of the statements nested in it."""
    for child in node.children():
        if isinstance(child, n.Expression):
            yield from references(child)
        elif not isinstance(child, (n.Statement, n.Branch, n.CaseArm, n.Handler)):
            yield from references(child)


def _label(found: set[Chain], outer: Chain) -> str:
    """The frame directly inside `outer` that every reference needs, HERE, MIXED or NEUTRAL."""
    if not found:
        return NEUTRAL
    nexts = {c[len(outer)] if len(c) > len(outer) and c[: len(outer)] == outer else (HERE if c == outer else MIXED) for c in found}
    return nexts.pop() if len(nexts) == 1 else MIXED


def _frame_dependent(stmt: n.Statement) -> bool:
    """A statement whose value depends on its FRAME block: it reads HERE or writes a POSE/TRANSL literal."""
    for node in stmt.walk():
        if isinstance(node, n.Name) and node.id == "HERE":
            return True
        if isinstance(node, n.Call) and isinstance(node.function, n.Name) and node.function.id in ("POSE", "TRANSL"):
            return True
    return False


def functions_of(body: n.Body) -> frozenset[str]:
    """The names of a program's FUNCs (declared at the top level)."""
    return frozenset(s.name.id for s in body if isinstance(s, n.Routine) and s.kind == "FUNC")


def _function_motion(stmt: n.Statement, functions: frozenset[str]) -> bool:
    """`LMOVE ARM TO f` or `ALONG f` with a FUNC f: its poses are relative to the FRAME block it stands in, which no
    position it names implies (so the block is neither inserted around it nor removed from around it)."""
    return isinstance(stmt, n.Motion) and any(isinstance(e, n.Name) and e.id in functions for e in (stmt.target, stmt.path))


def _holds_function_motion(body: n.Body, functions: frozenset[str]) -> bool:
    """A function-space motion in the body, in blocks nested in it but not inside FRAME blocks of their own."""
    stack: list[n.Node] = list(body)
    while stack:
        node = stack.pop()
        if isinstance(node, n.Statement) and _function_motion(node, functions):
            return True
        stack.extend(c for c in node.children() if isinstance(c, (n.Statement, n.Branch, n.CaseArm, n.Handler))
                     and not isinstance(c, n.FrameBlock))
    return False


def _map_bodies(stmt: n.Statement, fn) -> n.Statement:  # type: ignore[no-untyped-def]
    """The statement with `fn` applied to each of its blocks."""
    if isinstance(stmt, n.If):
        branches = tuple(dataclasses.replace(b, body=fn(b.body)) for b in stmt.branches)
        else_body = fn(stmt.else_body) if stmt.else_body is not None else None
        return dataclasses.replace(stmt, branches=branches, else_body=else_body)
    if isinstance(stmt, n.Case):
        arms = tuple(dataclasses.replace(a, body=fn(a.body)) for a in stmt.arms)
        else_arm = dataclasses.replace(stmt.else_arm, body=fn(stmt.else_arm.body)) if stmt.else_arm else None
        return dataclasses.replace(stmt, arms=arms, else_arm=else_arm)
    if isinstance(stmt, n.Try):
        handlers = tuple(dataclasses.replace(h, body=fn(h.body)) for h in stmt.handlers)
        return dataclasses.replace(stmt, body=fn(stmt.body), handlers=handlers)
    if isinstance(stmt, (n.While, n.For, n.FrameBlock, n.Routine)):
        return dataclasses.replace(stmt, body=fn(stmt.body))
    return stmt


def wrap(body: n.Body, outer: Chain, chains: Mapping[str, Chain], functions: frozenset[str] = frozenset()) -> n.Body:
    """Group the statements of a body by the frame they need and wrap each group in FRAME ... ENDFRAME."""
    labels = []
    for stmt in body:
        if _function_motion(stmt, functions):
            labels.append(HERE)  # in the frame it is written in: never pulled into a block around its neighbours
        elif isinstance(stmt, n.Routine):
            labels.append(NEUTRAL)
        elif isinstance(stmt, n.FrameBlock):
            labels.append(MIXED)  # written by the programmer: left where it is
        elif isinstance(stmt, n.Return) and not _frame_dependent(stmt):
            labels.append(NEUTRAL)  # `RETURN OFFS(corner1, ...)` gives the same pose in any block: no FRAME needed
        elif functions and _holds_function_motion((stmt,), functions):
            labels.append(MIXED)  # its blocks are wrapped statement by statement, the function-space motion left out
        else:
            labels.append(_label(_chains(stmt, chains), outer))
    out: list[n.Statement] = []
    i = 0
    while i < len(body):
        label, stmt = labels[i], body[i]
        if label in (NEUTRAL, HERE, MIXED):
            out.append(_inside(stmt, outer, chains, label, functions))
            i += 1
            continue
        last = i
        for j in range(i + 1, len(body)):
            if labels[j] == label:
                last = j
            elif labels[j] != NEUTRAL:
                break
        inner = outer + (label,)
        group = wrap(body[i: last + 1], inner, chains, functions)
        out.append(n.FrameBlock(n.Name(label), group))
        i = last + 1
    return tuple(out)


def _inside(stmt: n.Statement, outer: Chain, chains: Mapping[str, Chain], label: str, functions: frozenset[str]) -> n.Statement:
    """Blocks inside a statement that is not wrapped as a whole get their own FRAME blocks."""
    if isinstance(stmt, n.Routine):
        return _map_bodies(stmt, lambda b: wrap(b, (), chains, functions))
    if isinstance(stmt, n.FrameBlock):
        return _map_bodies(stmt, lambda b: wrap(b, outer + (stmt.frame.id,), chains, functions))
    if label == MIXED:
        return _map_bodies(stmt, lambda b: wrap(b, outer, chains, functions))
    return stmt


def insert_frame_blocks(job: Job) -> Job:
    """FRAME f ... ENDFRAME around the statements from the first to the last that use f's positions (nested as frames nest)."""
    body = wrap(job.program.body, (), job.chains, functions_of(job.program.body))
    return dataclasses.replace(job, program=dataclasses.replace(job.program, body=body))


def strip(body: n.Body, frames: frozenset[str], functions: frozenset[str] = frozenset()) -> n.Body:
    """The body with every FRAME block of `frames` (without comments of its own) replaced by its statements; a block
    around a motion to or along a FUNC stays (the FUNC's poses are relative to it, off-line too)."""
    out: list[n.Statement] = []
    for stmt in body:
        if (isinstance(stmt, n.FrameBlock) and stmt.frame.id in frames and stmt.header_comment is None and stmt.comment is None
                and not _holds_function_motion(stmt.body, functions)):
            out.extend(strip(stmt.body, frames, functions))
        else:
            out.append(_map_bodies(stmt, lambda b: strip(b, frames, functions)))
    return tuple(out)


def remove_frame_blocks(job: Job) -> Job:
    """The FRAME blocks of the world's on-line frames are removed: off-line, positions carry their frames."""
    frames = frozenset(o.name for o in job.world.objects if o.online_frame or o.axis is not None)
    body = strip(job.program.body, frames, functions_of(job.program.body))
    return dataclasses.replace(job, program=dataclasses.replace(job.program, body=body))
