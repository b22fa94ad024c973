"""`orc fmt FILE [--check] [--write]`: canonical text from the syntax tree, comments kept."""

from __future__ import annotations

import argparse
import sys

from orc_rpl.atomic import write_text_atomic
from orc_rpl.errors import SourceError, UsageError
from orc_rpl.syntax.files import canonical_text, is_offline, parse_file


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    parser = subparsers.add_parser("fmt", help="format programs canonically",
                                   description="Print programs in canonical form (comments kept). "
                                               "--check exits 1 when a file is not canonical; --write replaces it atomically.")
    parser.add_argument("files", nargs="+", metavar="FILE", help="program files (.rpl, .orl)")
    parser.add_argument("--world", metavar="FILE", help="world model: off-line programs' world paths are checked before formatting")
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--check", action="store_true", help="only report files that are not canonical (exit 1)")
    mode.add_argument("--write", action="store_true", help="rewrite files in place, atomically")
    return parser


def format_text(path: str, world: str | None = None) -> tuple[str, str]:
    """The file's text and its canonical form (off-line programs in the off-line syntax)."""
    text, program = parse_file(path)
    if not is_offline(path):
        return text, canonical_text(program, path)
    if world is not None:
        from orc_rpl.transform.checks import load_world_file
        from orc_rpl.transform.references import world_diagnostics

        diagnostics = world_diagnostics(program, load_world_file(world), path)
        if diagnostics:
            raise SourceError(diagnostics, text)
    return text, canonical_text(program, path)


def run(args: argparse.Namespace) -> int:
    status = 0
    for path in args.files:
        try:
            text, canonical = format_text(path, getattr(args, "world", None))
        except UsageError as error:
            sys.stderr.write(f"orc fmt: error: {error}\n")
            return 2
        except SourceError as error:
            sys.stdout.write(error.format() + "\n")
            sys.stderr.write(f"orc fmt: {path} has syntax errors; nothing was changed\n")
            return 2
        if args.check:
            if text != canonical:
                sys.stderr.write(f"would reformat {path}\n")
                status = max(status, 1)
        elif args.write:
            if text != canonical:
                write_text_atomic(path, canonical)
                sys.stderr.write(f"reformatted {path}\n")
        else:
            sys.stdout.write(canonical)
    return status
