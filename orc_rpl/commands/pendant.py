"""`orc pendant [FILE]`: the full-screen teach pendant on the virtual robot; offers to recover a killed session's edits."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterable
from contextlib import ExitStack
from pathlib import Path

from orc_rpl.commands import bus_robot
from orc_rpl.commands.run import add_cell_options, equipment_script, paced_priority
from orc_rpl.errors import OrcError, UsageError
from orc_rpl.syntax.files import interrupted_mark


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    parser = subparsers.add_parser(
        "pendant", help="the teach pendant: jog, teach, edit, step and run on the virtual robot",
        description="A full-screen teach pendant for an on-line program on the simulated cell. Type an RPL "
                    "statement to execute it at once, or a :command (:help lists them). Every edit is journaled: "
                    "after a crash, the next start offers to recover it. When standard input is not a terminal, "
                    "its lines are run one by one as if typed (exit 1 if one failed).")
    parser.add_argument("file", metavar="FILE", nargs="?", help="program file (.rpl); created on :save if missing")
    parser.add_argument("--world", metavar="DIR|FILE", help="folder with the program's simulated-IO script (<name>.sim.yaml), "
                        "or the world model (YAML) of the cell: its tracks and positioners are jogged with :jog axis NAME AMOUNT")
    parser.add_argument("--robot", metavar="NAME", default="irb2400", help="robot model (default irb2400)")
    parser.add_argument("--backend", choices=("servo", "kinematic"), default="servo",
                        help="servo: MuJoCo cell with servo loops (default); kinematic: fast, no :snapshot")
    bus_robot.add_options(parser)
    add_cell_options(parser)
    view = parser.add_argument_group("3D view (the [view] extra)")
    view.add_argument("--view", action="store_true",
                      help="show the cell in a 3D view in the browser; it follows jogging, teaching, stepping and running")
    view.add_argument("--host", metavar="ADDRESS", help="with --view: listen on ADDRESS instead of 127.0.0.1")
    view.add_argument("--view-port", metavar="PORT", type=int, help="with --view: the first port to try (default 8080)")
    recovery = parser.add_mutually_exclusive_group()
    recovery.add_argument("--recover", action="store_true", help="take unsaved edits from the journal without asking")
    recovery.add_argument("--discard", action="store_true", help="discard unsaved edits in the journal without asking")
    return parser


def _fail(message: str) -> int:
    sys.stderr.write(f"orc pendant: error: {message}\n")
    return 2


def _ask_recovery(session: object, args: argparse.Namespace) -> str:
    """Recover, discard or keep (answer asked on the terminal before the full screen starts)."""
    pending = session.editor.pending_recovery()  # type: ignore[attr-defined]
    if pending is None:
        return ""
    if args.recover:
        return session.editor.recover()  # type: ignore[attr-defined]
    if args.discard:
        return session.editor.discard_recovery()  # type: ignore[attr-defined]
    if not sys.stdin.isatty():
        return f"{pending} in the journal: start with --recover or --discard"
    answer = input(f"orc pendant: {session.editor.path} has {pending} from a session that did not save.\n"  # type: ignore[attr-defined]
                   "Recover them? [Y/n] ").strip().lower()
    if answer in ("", "y", "yes"):
        return session.editor.recover()  # type: ignore[attr-defined]
    return session.editor.discard_recovery()  # type: ignore[attr-defined]


def _check_view_options(args: argparse.Namespace) -> None:
    """--host and --view-port need --view; --view needs the extra."""
    if not args.view:
        for option in ("host", "view_port"):
            if getattr(args, option) is not None:
                raise UsageError(f"--{option.replace('_', '-')} needs --view")
        return
    try:
        from orc_rpl.view.server import check_port
    except ImportError as error:
        raise UsageError(f"--view needs the view extra (pip install 'orc_rpl[view]'): {error}") from None
    check_port(args.view_port)


def _watching(args: argparse.Namespace) -> object:
    """The 3D view's settings; the pendant never waits for the browser (the robot moves only when told)."""
    from orc_rpl.view.server import DEFAULT_HOST, DEFAULT_PORT
    from orc_rpl.view.watch import Watching

    return Watching(view=True, host=args.host or DEFAULT_HOST,
                    port=DEFAULT_PORT if args.view_port is None else args.view_port, interactive=False)


def run(args: argparse.Namespace) -> int:
    from orc_rpl.robot.robots import ROBOTS

    try:
        if args.robot not in ROBOTS:
            raise UsageError(f"--robot: unknown robot {args.robot!r}; known robots: {', '.join(ROBOTS.names())}")
        if args.world is not None and not Path(args.world).is_dir() and not Path(args.world).is_file():
            raise UsageError(f"--world: '{args.world}' is neither a directory nor a world model file")
        if args.file is not None and Path(args.file).suffix != ".rpl":
            raise UsageError(f"'{args.file}': a program file must end in .rpl")
        if args.file is not None and Path(args.file).is_dir():
            raise UsageError(f"'{args.file}' is a directory")
        bus_robot.check_options(args)
        _check_view_options(args)
        if args.file is not None and not Path(args.file).resolve().parent.is_dir():
            raise UsageError(f"the folder of '{args.file}' does not exist (:save and the journal write there)")
        if args.file is not None and Path(args.file).exists():
            if interrupted_mark(args.file).exists():
                raise UsageError(f"'{args.file}' may be out of step with its world: the conversion that wrote them was "
                                 f"interrupted; convert again, or delete '{interrupted_mark(args.file).name}'")
    except UsageError as error:
        return _fail(str(error))
    try:
        return _run(args)
    except OrcError as error:
        return _fail(str(error))


def _run(args: argparse.Namespace) -> int:
    from orc_rpl.commands.run import simulated_plant, simulated_seed, world_cell
    from orc_rpl.executive.cell_robot import CellRobot
    from orc_rpl.executive.sim_io import load_script
    from orc_rpl.motion.sensors import SensorManager
    from orc_rpl.pendant.app import PendantApp
    from orc_rpl.pendant.robot import PendantRobot
    from orc_rpl.pendant.session import PendantSession

    interactive = sys.stdin.isatty()
    if args.port is not None:
        robot = PendantRobot(bus_robot.connect(args, record=False))  # a real (or emulated) arm on a servo bus
    else:
        world_file = args.world if args.world is not None and Path(args.world).is_file() else None
        cell, cell_world = world_cell(world_file, args.robot)
        name = cell.robot if cell is not None else args.robot
        cell_robot = CellRobot.virtual(name, backend=args.backend, plant=simulated_plant(args, name), seed=simulated_seed(args), cell=cell)
        if cell_world is not None:
            cell_robot.attach_world(cell_world)  # its tracks and positioners: jogged, taught, moved with the arm
        robot = PendantRobot(cell_robot)
        # A simulated session touches no device unless asked (the manager INSTALL would otherwise make for this robot).
        robot.sensors = SensorManager(allow_devices=args.allow_devices)  # type: ignore[attr-defined]
    session = PendantSession(args.file, robot=robot, synchronous=not interactive)
    try:
        if not interactive and session.editor.pending_recovery() is not None and not (args.recover or args.discard):
            # a script's edits would bury the killed session's in the journal: the user decides first
            return _fail(f"{session.editor.path} has {session.editor.pending_recovery()} in its journal; "
                         "start with --recover or --discard")
        message = _ask_recovery(session, args)
        io_script = equipment_script(args, args.file, args.world if args.world is None or Path(args.world).is_dir() else None)
        if io_script is not None:
            load_script(io_script, robot.io, lambda: getattr(robot, "plant_tcp_pose", robot.tcp_pose)(session.execution.tool_pose()),
                        push=getattr(robot, "push_on_arm", None))
        with ExitStack() as stack:
            if args.view:
                from orc_rpl.view.watch import watch

                watchers = stack.enter_context(watch(session.execution.executive(), robot, session.editor.program,
                                                     None, session.registry, _watching(args)))  # type: ignore[arg-type]
                stack.callback(session.close)  # stop feeding the view before it closes
                session.show_in(watchers.live, watchers.url)  # type: ignore[arg-type]
                message = "\n".join(filter(None, (message, f"the 3D view is at {watchers.url}")))
            if not interactive:
                return _run_script(session, sys.stdin, message)
            if not args.view:
                return PendantApp(session, message=message).run()
            # paced to the wall clock beside a browser drawing the view: the motion cycle at real-time priority, as
            # `orc run --view` has it; a refusal is the pendant's first message
            refusal: list[str] = []
            with paced_priority(True, "orc pendant", refusal.append):
                return PendantApp(session, message="\n".join(filter(None, (message, *refusal)))).run()
    finally:
        session.close()


def _run_script(session: object, lines: Iterable[str], message: str) -> int:
    """Standard input is not a terminal: each line is typed at the command line in turn, its answer printed.

    Exit 0 when every line succeeded, 1 when one failed (the others still ran); unsaved edits stay in the
    journal, as after a crash, and the next start offers them.
    """
    from orc_rpl.pendant.commands import run_line

    if message:
        sys.stdout.write(message + "\n")
    failed = 0
    for number, line in enumerate(lines, start=1):
        outcome = run_line(session, line.rstrip("\n"))  # type: ignore[arg-type]
        if outcome.text:
            sys.stdout.write(outcome.text + "\n")
        if outcome.error:
            failed += 1
            sys.stderr.write(f"<stdin>:{number}: error in {line.strip()!r}\n")
        if outcome.quit:
            break
    if session.editor.modified:  # type: ignore[attr-defined]
        sys.stderr.write(f"orc pendant: unsaved edits of {session.editor.path} are kept in its journal "  # type: ignore[attr-defined]
                         "(:save writes the program)\n")
    return 1 if failed else 0

