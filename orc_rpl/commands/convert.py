"""`orc convert FILE --to online|offline --world WORLD -o OUT`: the exact transformation between the two representations."""

from __future__ import annotations

import argparse
import dataclasses
import os
import re
import sys
from pathlib import Path

from orc_rpl.commands.outputs import check_outputs, quiet_stdout, write_all_atomic
from orc_rpl.errors import OrcError, SourceError, UsageError
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.files import declared_world, is_offline, parse_file

#: The comment that names an off-line program's world model (`# world: ../../worlds/cell.yaml`).
_WORLD_COMMENT = re.compile(r"\s*world:\s*\S+\s*$")


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    parser = subparsers.add_parser(
        "convert", help="transform a program between the off-line (.orl) and on-line (.rpl) representations",
        description="Off-line -> on-line: positions become named on-line positions relative to their on-line frames, "
                    "tool chains collapse, FRAME blocks are inserted. On-line -> off-line: the inverse; positions taught "
                    "or touched up on-line go into the world model (--world), which is created when it does not exist. "
                    "Every output is written atomically, and only when the whole conversion succeeded.")
    parser.add_argument("file", metavar="FILE", help="program to convert (.orl or .rpl)")
    parser.add_argument("--to", choices=("online", "offline"), help="target representation (default: the other one)")
    parser.add_argument("--world", metavar="WORLD", help="the off-line world model (YAML); written when converting to off-line")
    parser.add_argument("-o", "--output", metavar="OUT", help="output program (default: standard output)")
    parser.add_argument("--online-world", metavar="FILE",
                        help="also write the reduced on-line world (model attributes replaced by keys into WORLD)")
    parser.add_argument("--base", metavar="FILE",
                        help="the program (in the target representation) this one was converted from: every statement "
                             "that did not change keeps its text from FILE byte for byte; changed and new statements "
                             "are printed canonically (orc fmt gives the canonical text of all)")
    return parser


def _target(args: argparse.Namespace) -> str:
    target = args.to or ("online" if is_offline(args.file) else "offline")
    if (target == "online") != is_offline(args.file):
        kind = "an off-line" if is_offline(args.file) else "an on-line"
        raise UsageError(f"'{args.file}' is already {kind} program; --to {target} converts the other way")
    if args.output is not None:
        wanted = ".rpl" if target == "online" else ".orl"
        if Path(args.output).suffix != wanted:
            raise UsageError(f"-o: an {target} program is written to a '{wanted}' file, got '{args.output}'")
    return target


def convert(args: argparse.Namespace) -> dict[str, str]:
    """Every output file's text, computed before anything is written."""
    from orc_rpl.transform.checks import load_world_file
    from orc_rpl.transform.pipeline import to_offline, to_online

    target = _target(args)
    text, program = parse_file(args.file)
    outputs: dict[str, str] = {}
    if target == "online":
        world_path = args.world or declared_world(args.file, text)
        if world_path is None:
            raise UsageError(f"--world: '{args.file}' is an off-line program; give its world model")
        check_outputs({"the world model": str(world_path)}, {"-o": args.output, "--online-world": args.online_world})
        world = load_world_file(world_path)
        _refuse_check_errors(program, text, args.file, world)
        job = to_online(program, world, args.file, text, reduce=bool(args.online_world))
        # The world line is the off-line program's: the on-line program travels with its (reduced) world instead.
        outputs[args.output or "-"] = _print(_without_world_line(job.program), args.base, offline=False)
        if args.online_world:
            outputs[args.online_world] = job.world.dump()
        return outputs
    world = load_world_file(args.world) if args.world and Path(args.world).exists() else None
    _refuse_check_errors(program, text, args.file, None, world)
    job = to_offline(program, world, args.file, move_declarations=True)
    result = job.program
    if args.world:
        result = _with_world_line(result, args.world, args.output or args.file, _base(args.base, offline=True))
    outputs[args.output or "-"] = _print(result, args.base, offline=True)
    if args.world:
        if world is None or job.world.dump() != world.dump():
            outputs[args.world] = job.world.dump()
    elif job.world.objects:
        raise UsageError("--world: the program's positions need a world model file to go into")
    return outputs


def _base(path: str | None, offline: bool) -> tuple[str, n.Program] | None:
    """The --base program's text and tree (UsageError when it is not a program of the target representation)."""
    if path is None:
        return None
    if is_offline(path) != offline:
        kind = "an off-line (.orl)" if offline else "an on-line (.rpl)"
        raise UsageError(f"--base: the layout of the output comes from {kind} program, got '{path}'")
    if not Path(path).is_file():
        raise UsageError(f"--base: '{path}' does not exist")
    return parse_file(path)


def _print(program: n.Program, base_path: str | None, offline: bool) -> str:
    """The output text: canonical, or in the layout of --base for the statements that did not change."""
    from orc_rpl.syntax.layout import print_offline_keeping, print_online_keeping
    from orc_rpl.syntax.offline_printer import print_offline
    from orc_rpl.syntax.printer import print_program

    base = _base(base_path, offline)
    if base is None:
        return print_offline(program) if offline else print_program(program)
    return (print_offline_keeping if offline else print_online_keeping)(program, base[0], base[1])


def _refuse_check_errors(program: n.Program, text: str, path: str, world, cell=None) -> None:  # type: ignore[no-untyped-def]
    """A program `orc check` rejects is not converted: its errors, as `orc check` prints them (an on-line program in
    the cell `cell`, whose moving frames it may name)."""
    from orc_rpl.application.registry import default_registry
    from orc_rpl.checking.checker import check_program
    from orc_rpl.transform.checks import check_offline

    registry = default_registry()
    from orc_rpl.transform.loading import moving_frames

    found = (check_offline(program, world, path, text, registry) if world is not None else
             check_program(program, path, registry, moving_frames=moving_frames(cell) if cell is not None else None))
    if found:
        raise SourceError(found, text)


def _world_line_at(program: n.Program) -> int | None:
    """Where the `# world: FILE` comment stands among the program's leading comment lines."""
    for i, stmt in enumerate(program.body):
        if not isinstance(stmt, n.Comment):
            return None
        if _WORLD_COMMENT.match(stmt.text):
            return i
    return None


def _without_world_line(program: n.Program) -> n.Program:
    at = _world_line_at(program)
    return program if at is None else dataclasses.replace(program, body=program.body[:at] + program.body[at + 1:])


def _with_world_line(program: n.Program, world: str, output: str, base: tuple[str, n.Program] | None = None) -> n.Program:
    """The program naming the world it was converted with, relative to the file it is written to, as its first line
    (the --base program's own world line, as written, when it names that world from there)."""
    relative = Path(os.path.relpath(Path(world).resolve(), Path(output).resolve().parent)).as_posix()
    line, at = n.Comment(f" world: {relative}"), 0
    found = _world_line_at(base[1]) if base is not None else None
    if base is not None and found is not None:
        written = base[1].body[found]
        assert isinstance(written, n.Comment)
        named = (Path(output).resolve().parent / written.text.split(":", 1)[1].strip()).resolve()
        if named == Path(world).resolve():
            line = written
            at = found
    body = _without_world_line(program).body
    if not all(isinstance(stmt, n.Comment) for stmt in body[:at]):
        at = 0
    return dataclasses.replace(program, body=body[:at] + (line,) + body[at:])


def _check_paths(args: argparse.Namespace) -> None:
    """Outputs that are inputs or each other are refused before anything is read; --world may be updated in place."""
    to_offline = (args.to or ("online" if is_offline(args.file) else "offline")) == "offline"
    check_outputs({"FILE": args.file, "--world": args.world, "--base": args.base},
                  {"-o": args.output, "--online-world": args.online_world, "--world": args.world if to_offline else None},
                  in_place=(("--world", "--world"),))


def run(args: argparse.Namespace) -> int:
    try:
        _check_paths(args)
        outputs = convert(args)
    except UsageError as error:
        sys.stderr.write(f"orc convert: error: {error}\n")
        return 2
    except SourceError as error:
        sys.stderr.write(error.format() + "\n")
        sys.stderr.write("orc convert: nothing was written\n")
        return 2
    except OrcError as error:
        sys.stderr.write(f"orc convert: error: {error}\nnothing was written\n")
        return 2
    files = {path: text for path, text in outputs.items() if path != "-"}
    try:
        write_all_atomic(files, args.output)
    except OSError as error:
        sys.stderr.write(f"orc convert: error: cannot write '{error.filename or ', '.join(files)}': {error.strerror}\n")
        return 2
    for path in files:
        sys.stderr.write(f"wrote {path}\n")
    if "-" in outputs:
        try:
            sys.stdout.write(outputs["-"])
            sys.stdout.flush()
        except BrokenPipeError:
            quiet_stdout()
    return 0
