"""The `orc` command: one subcommand per module in `orc_rpl.commands`; exit codes 0 ok, 1 run-time failure, 2 usage or check errors."""

from __future__ import annotations

import argparse
import importlib
import sys

#: Subcommand modules under orc_rpl.commands, in the order `orc --help` lists them.
COMMANDS: tuple[str, ...] = ("check", "fmt", "run", "convert", "diff", "pendant", "lsp", "view")


class _Parser(argparse.ArgumentParser):
    """argparse that exits with 2 and a one-line message naming the bad argument."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.print_usage(sys.stderr)
        sys.stderr.write(f"{self.prog}: error: {message}\n")
        raise SystemExit(2)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every subcommand."""
    parser = _Parser(prog="orc", description="Open Robot Control: check, format, run and convert robot programs.")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name in COMMANDS:
        module = importlib.import_module(f"orc_rpl.commands.{name}")
        sub = module.add_parser(subparsers)
        sub.set_defaults(handler=module.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of `orc` and `python -m orc_rpl`."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help(sys.stderr)
        return 2
    from orc_rpl.application.registry import FeaturesMissing

    try:
        return int(args.handler(args))
    except FeaturesMissing as error:  # a checkout that was never installed: say how to fix it
        sys.stderr.write(f"orc: {error}\n")
        return 2
    except KeyboardInterrupt:
        sys.stderr.write("orc: interrupted\n")
        return 130
