"""`orc view WORLD.yaml [PROGRAM]`: the cell, the world's objects and frames and a program's positions in the browser, nothing run."""

from __future__ import annotations

import argparse
import sys
import threading
from pathlib import Path

from orc_rpl.errors import OrcError, SourceError, UsageError


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    parser = subparsers.add_parser(
        "view", help="show a world and a program's positions in a 3D view in the browser",
        description="Show the cell of a world model, its objects and frames, and the positions a program declares, "
                    "in a 3D view in the browser (nothing moves). Serves until interrupted (Ctrl-C), or until Enter "
                    "at a terminal. Needs the [view] extra.")
    parser.add_argument("world", metavar="WORLD.yaml", help="world model of the cell")
    parser.add_argument("program", metavar="PROGRAM", nargs="?", help="a program (.rpl, or .orl of this world) whose positions to show")
    parser.add_argument("--robot", metavar="NAME", help="robot model (default: the world's, else irb2400)")
    parser.add_argument("--host", metavar="ADDRESS", help="listen on ADDRESS instead of 127.0.0.1")
    parser.add_argument("--view-port", metavar="PORT", type=int, help="the first port to try (default 8080)")
    return parser


def _fail(message: str, code: int = 2) -> int:
    sys.stderr.write(f"orc view: error: {message}\n")
    return code


def run(args: argparse.Namespace) -> int:
    from orc_rpl.application.standard_behaviour import runtime_registry
    from orc_rpl.commands.run import check
    from orc_rpl.robot.robots import ROBOTS
    from orc_rpl.transform.loading import load_program
    from orc_rpl.world import load_world

    try:
        if not Path(args.world).is_file():
            raise UsageError(f"world model '{args.world}' does not exist")
        world = load_world(args.world)
        robot_name = args.robot or (world.robot.model if world.robot is not None and world.robot.model in ROBOTS else "irb2400")
        if robot_name not in ROBOTS:
            raise UsageError(f"--robot: unknown robot {robot_name!r}; known robots: {', '.join(ROBOTS.names())}")
        source = program = None
        if args.program is not None:
            source, program = load_program(args.program, args.world)
        from orc_rpl.view.server import DEFAULT_HOST, DEFAULT_PORT, check_port

        check_port(args.view_port)
    except SourceError as error:
        sys.stderr.write(error.format() + "\n")
        return 2
    except ImportError as error:
        return _fail(f"the 3D view needs the view extra (pip install 'orc_rpl[view]'): {error}")
    except OrcError as error:
        return _fail(str(error))
    registry = runtime_registry()
    if program is not None:
        diagnostics = check(program, args.program, registry, cell_world=world)  # its moving frames may be named
        if diagnostics:
            for diagnostic in diagnostics:
                sys.stderr.write(diagnostic.format(source) + "\n")
            return _fail(f"{len(diagnostics)} check error{'s' if len(diagnostics) != 1 else ''} in {args.program}")
    try:
        return _serve(args, world, program, registry, robot_name, args.host or DEFAULT_HOST,
                      DEFAULT_PORT if args.view_port is None else args.view_port)
    except UsageError as error:
        return _fail(str(error))
    except OrcError as error:
        return _fail(str(error), 1)


def _serve(args: argparse.Namespace, world: object, program: object, registry: object, robot_name: str,
           host: str, port: int) -> int:
    from orc_rpl.view.server import close_server, open_server, url_of
    from orc_rpl.view.still import show_still

    server = open_server(host, port)
    try:
        show_still(server, world, program, registry, robot_name, f"{args.world}" + (f" · {args.program}" if args.program else ""),
                   args.program or "<program>")
        sys.stderr.write(f"orc: the 3D view is at {url_of(server)} (Ctrl-C to close it)\n")
        sys.stderr.flush()
        try:
            if sys.stdin.isatty():
                sys.stdin.readline()
            else:
                threading.Event().wait()
        except KeyboardInterrupt:
            pass
    finally:
        close_server(server)
    return 0
