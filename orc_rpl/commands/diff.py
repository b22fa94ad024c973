"""`orc diff A B`: the semantic difference of two programs, on-line or off-line: positions and statements, not bytes."""

from __future__ import annotations

import argparse
import difflib
import sys

from orc_rpl.errors import OrcError, SourceError, UsageError
from orc_rpl.syntax import nodes as n

#: Positions closer than this (m, rad) are the same position.
TOLERANCE = 1e-6


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    parser = subparsers.add_parser(
        "diff", help="show the semantic difference of two programs (.rpl or .orl)",
        description="Compare two programs in their on-line form: positions (added, removed, moved) and statements "
                    "(comments and layout ignored). Exit 0 when they are the same, 1 when they differ, 2 on errors.")
    parser.add_argument("a", metavar="A", help="first program")
    parser.add_argument("b", metavar="B", help="second program")
    parser.add_argument("--world", metavar="WORLD", help="world model of off-line programs (both, unless --world-b)")
    parser.add_argument("--world-b", metavar="WORLD", help="world model of B when it differs from A's")
    return parser


def positions(program: n.Program) -> dict[str, tuple[str, object, str]]:
    """Name -> (kind, value, text) of every FRAME, TOOL, POS and PATH declaration at the top level."""
    from orc_rpl.syntax.printer import expression
    from orc_rpl.transform.poses import literal_path, literal_pose

    out: dict[str, tuple[str, object, str]] = {}
    for stmt in program.body:
        if isinstance(stmt, n.Declaration) and stmt.kind in ("FRAME", "TOOL", "POS", "PATH"):
            frame = stmt.frame.id if stmt.frame is not None else "world"
            value = literal_pose(stmt.value, frame) if stmt.kind != "PATH" else literal_path(stmt.value, frame)
            text = expression(stmt.value) + (f" IN {frame}" if stmt.frame is not None else "")
            out[stmt.name.id] = (stmt.kind, value if value is not None else stmt.value, text)
    return out


def _same(a: object, b: object) -> bool:
    import numpy as np

    from orc_rpl.world import Pose

    if isinstance(a, Pose) and isinstance(b, Pose):
        # (0, 180deg, 0) and (180deg, 0, 180deg) are one pose: compare transforms, not the numbers written
        return a.frame == b.frame and bool(np.allclose(a.matrix(), b.matrix(), rtol=0.0, atol=TOLERANCE))
    if isinstance(a, tuple) and isinstance(b, tuple):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    return a == b


def _shown_change(a: object, b: object) -> list[str]:
    """`    (50.0, -40.0, 60.0) mm, ... -> (...) in base_plate`: a changed literal pose in the one display convention."""
    from orc_rpl.world import Pose
    from orc_rpl.world.pose import shown_pose

    if not (isinstance(a, Pose) and isinstance(b, Pose)):
        return []
    where = f" in {b.frame}" if a.frame == b.frame else f" in {a.frame} -> in {b.frame}"
    return [f"    {shown_pose(a).text()} -> {shown_pose(b).text()}{where}"]


def statements(program: n.Program) -> list[str]:
    """The program's statements as canonical on-line lines, without comments, blank lines and position declarations."""
    from orc_rpl.syntax.printer import print_program

    body = tuple(s for s in program.body if not (isinstance(s, n.Declaration) and s.kind in ("FRAME", "TOOL", "POS", "PATH")))
    lines = print_program(n.Program(_without_comments(body))).splitlines()
    return [line for line in lines if line.strip()]


def _without_comments(body: n.Body) -> n.Body:
    import dataclasses

    out = []
    for stmt in body:
        if isinstance(stmt, (n.Comment, n.Blank)):
            continue
        changes = {f.name: None for f in dataclasses.fields(stmt) if f.name in ("comment", "header_comment", "else_comment")}
        for field in dataclasses.fields(stmt):
            value = getattr(stmt, field.name)
            if field.name in ("body", "else_body") and isinstance(value, tuple):
                changes[field.name] = _without_comments(value)
        out.append(dataclasses.replace(stmt, **changes))
    return tuple(out)


def difference(a: n.Program, b: n.Program, name_a: str = "A", name_b: str = "B") -> list[str]:
    """The report lines; empty when the programs do the same."""
    lines: list[str] = []
    pa, pb = positions(a), positions(b)
    for name in sorted(set(pa) | set(pb)):
        if name not in pb:
            lines.append(f"- {pa[name][0]} {name} (only in {name_a})")
        elif name not in pa:
            lines.append(f"+ {pb[name][0]} {name} (only in {name_b})")
        elif not _same(pa[name][1], pb[name][1]):
            lines.append(f"~ {pa[name][0]} {name} changed: {pa[name][2]} -> {pb[name][2]}")
            lines.extend(_shown_change(pa[name][1], pb[name][1]))
    diff = list(difflib.unified_diff(statements(a), statements(b), name_a, name_b, lineterm="", n=1))
    return lines + diff


def run(args: argparse.Namespace) -> int:
    from orc_rpl.transform.loading import load_program

    try:
        _, a = load_program(args.a, args.world)
        _, b = load_program(args.b, args.world_b or args.world)
    except UsageError as error:
        sys.stderr.write(f"orc diff: error: {error}\n")
        return 2
    except SourceError as error:
        sys.stderr.write(error.format() + "\n")
        return 2
    except OrcError as error:
        sys.stderr.write(f"orc diff: error: {error}\n")
        return 2
    report = difference(a, b, args.a, args.b)
    try:
        for line in report:
            sys.stdout.write(line + "\n")
        sys.stdout.flush()
    except BrokenPipeError:
        quiet_stdout()
    return 1 if report else 0


def quiet_stdout() -> None:
    """The reader went away (`orc diff A B | head`): drop the rest of the output without a traceback."""
    import os

    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())
