"""`orc check FILE...`: syntax and static checks; every error as `file:line:col: message` with a caret."""

from __future__ import annotations

import argparse
import sys

from orc_rpl.application.registry import default_registry
from orc_rpl.checking.checker import check_program
from orc_rpl.errors import Diagnostic, Location, SourceError, UsageError, capped
from orc_rpl.syntax.files import declared_world, is_offline, parse_file


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    parser = subparsers.add_parser("check", help="check programs for syntax and static errors",
                                   description="Check programs; exit 0 when clean, 2 when any error is found.")
    parser.add_argument("files", nargs="+", metavar="FILE", help="program files (.rpl, .orl)")
    parser.add_argument("--world", metavar="FILE", help="world model of off-line programs (else their '# world: FILE' line); "
                        "for on-line programs, the world whose soft and spatial attributes they read (pallet.next_row)")
    return parser


def _cell_of(path: str, text: str) -> str | None:
    """The cell named by an on-line program's `-- world: FILE` line, or None."""
    cell = declared_world(path, text)
    return None if cell is None else str(cell)


def check_file(path: str, registry=None, world: str | None = None) -> tuple[str | None, list[Diagnostic]]:  # type: ignore[no-untyped-def]
    """The source text and every diagnostic of one file (syntax errors first stop the static checks)."""
    try:
        text, program = parse_file(path)
    except SourceError as error:
        return error.source, error.diagnostics
    if is_offline(path):
        from orc_rpl.transform.checks import check_offline, load_world_file

        try:
            world_path = world if world is not None else declared_world(path, text)
            if world_path is None:  # without a world model only the syntax can be checked: say so, never "no errors"
                return text, [Diagnostic(Location(path, 1, 1), "syntax only: an off-line program's names are "
                                         "checked against its world model; give --world WORLD.yaml or a "
                                         "`# world: FILE` line", severity="note")]
            model = load_world_file(world_path)
        except SourceError as error:
            return error.source, error.diagnostics
        return text, check_offline(program, model, path, text, registry)
    try:
        world = world if world is not None else _cell_of(path, text)
    except SourceError as error:  # a `-- world:` line naming no world model
        return error.source, error.diagnostics
    if world is not None:  # an on-line program reads the soft and spatial attributes of the world it travels with
        from orc_rpl.transform.checks import load_world_file
        from orc_rpl.transform.loading import moving_frames, world_attributes

        try:
            model = load_world_file(world)
        except SourceError as error:
            return error.source, error.diagnostics
        return text, check_program(program, path, registry, world_attributes(model), moving_frames(model))
    return text, check_program(program, path, registry)


def run(args: argparse.Namespace) -> int:
    registry = default_registry()
    failed = 0
    errors = 0
    unreadable = 0
    syntax_only = 0
    for path in args.files:
        try:
            source, diagnostics = check_file(path, registry, getattr(args, "world", None))
        except UsageError as error:
            sys.stderr.write(f"orc check: error: {error}\n")
            unreadable += 1
            continue
        notes = [d for d in diagnostics if d.severity == "note"]
        syntax_only += bool(notes)
        diagnostics = [d for d in diagnostics if d.severity != "note"]
        for diagnostic in notes + capped(diagnostics):  # 16,000 errors in one file print 50 and a count
            sys.stdout.write(diagnostic.format(source) + "\n")
        if diagnostics:
            failed += 1
            errors += len(diagnostics)
    total = len(args.files)
    if failed or unreadable:
        if failed:
            sys.stderr.write(f"{errors} error{'s' if errors != 1 else ''} in {failed} of {total} file{'s' if total != 1 else ''}\n")
        return 2
    partly = f" ({syntax_only} for syntax only)" if syntax_only else ""
    sys.stderr.write(f"{total} file{'s' if total != 1 else ''} checked{partly}, no errors\n")
    return 0
