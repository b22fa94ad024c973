"""`orc run FILE`: check a program, run it on the virtual robot, print its output, report a summary and recordings."""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

from orc_rpl.atomic import write_text_atomic
from orc_rpl.commands import bus_robot
from orc_rpl.commands.interrupt import TimeLimit, positive_seconds, statement_budget, stop_on_path
from orc_rpl.commands.outputs import check_outputs, quiet_stdout
from orc_rpl.errors import Diagnostic, OrcError, SourceError, UsageError, capped
from orc_rpl.motion import scheduling
from orc_rpl.robot.plants import SIMULATED_PLANTS, check_elastic_gears

#: The progress display is refreshed every this many motion cycles.
PROGRESS_EVERY_TICKS = 125


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    parser = subparsers.add_parser(
        "run", help="run a program on the virtual robot",
        description="Check a program, then run it on the simulated cell. PRINT output goes to standard output, "
                    "progress and a summary to standard error. Exit 0 when it ends, 1 on a run-time error, "
                    "2 on usage, syntax or check errors.")
    parser.add_argument("file", metavar="FILE", help="program file (.rpl, or .orl with its world model)")
    parser.add_argument("--world", metavar="DIR|FILE", help="folder with the program's simulated-IO script (<name>.sim.yaml), "
                                                           "or the world model (YAML) of an off-line program (.orl), or the "
                                                           "world whose soft and spatial attributes an on-line program reads")
    parser.add_argument("--robot", metavar="NAME", default="irb2400", help="robot model (default irb2400)")
    parser.add_argument("--log", metavar="OUT.npz", help="write the recorded signals (q, q_ref, tau, tcp (flange), tool_tcp, s, process.*) as NPZ")
    parser.add_argument("--plot", metavar="OUT.png", help="plot the recorded signals as PNG")
    parser.add_argument("--summary-json", metavar="OUT.json", help="write status, cycle time, prints, error and the process outcomes as JSON")
    parser.add_argument("--realtime", action="store_true", help="pace the simulation to the wall clock")
    parser.add_argument("--timeout", metavar="SECONDS", type=positive_seconds,
                        help="stop the robot on its path after this much simulated time (status: interrupted)")
    parser.add_argument("--statement-budget", metavar="N", type=statement_budget, default=1_000_000,
                        help="stop a program that runs N statements without the robot moving or time passing "
                             "(default 1000000; 0: no budget)")
    add_cell_options(parser)
    parser.add_argument("--margins", action="store_true",
                        help="measure, per motion statement, the robot's nearest approach to the cell's objects and its "
                             "joints' margin to their limits (summary and --summary-json's `margins`)")
    parser.add_argument("--speed-override", metavar="PERCENT", default="100%",
                        help="scale every speed, e.g. 50%% (default 100%%)")
    view = parser.add_argument_group("3D view and video (the [view] extra)")
    view.add_argument("--view", action="store_true", help="show the run in a 3D view in the browser (paced to real time)")
    view.add_argument("--fast", action="store_true", help="with --view: do not pace; the view shows the latest state")
    view.add_argument("--host", metavar="ADDRESS", help="with --view: listen on ADDRESS instead of 127.0.0.1")
    view.add_argument("--view-port", metavar="PORT", type=int, help="with --view: the first port to try (default 8080)")
    view.add_argument("--video", metavar="OUT.mp4", help="film the run offscreen into an MP4 video")
    parser.add_argument("--set", metavar="NAME=VALUE", action="append", default=[],
                        help="replace the value of a top-level CONST, e.g. --set Vmax=1.2mps (repeatable)")
    bus_robot.add_options(parser)
    return parser


def watching(args: argparse.Namespace) -> Any:
    """The view and video options as a Watching (a UsageError for combinations that make no sense)."""
    if not args.view:
        for option in ("fast", "host", "view_port"):
            if getattr(args, option) not in (None, False):
                raise UsageError(f"--{option.replace('_', '-')} needs --view")
    if args.fast and args.realtime:
        raise UsageError("--fast and --realtime contradict each other")
    if args.video is not None:
        if not args.video.lower().endswith(".mp4"):
            raise UsageError(f"--video: the file must end in .mp4, got {args.video!r}")
        if not Path(args.video).resolve().parent.is_dir():
            raise UsageError(f"--video: the folder of '{args.video}' does not exist")
    if not (args.view or args.video):
        return None
    from orc_rpl.plant.gl import request_rendering

    if args.video:
        request_rendering()  # before MuJoCo is first imported: it picks its GL backend then
    try:
        from orc_rpl.view.server import DEFAULT_HOST, DEFAULT_PORT, check_port
        from orc_rpl.view.watch import Watching
    except ImportError as error:
        raise UsageError(f"--view and --video need the view extra (pip install 'orc_rpl[view]'): {error}") from None
    check_port(args.view_port)
    return Watching(view=args.view, host=args.host or DEFAULT_HOST,
                    port=DEFAULT_PORT if args.view_port is None else args.view_port,
                    video=args.video, interactive=sys.stdin.isatty() and sys.stderr.isatty())


def speed_override(text: str) -> float:
    """`50%` or `0.5` -> 0.5; a UsageError naming the option otherwise."""
    try:
        value = float(text[:-1]) / 100.0 if text.endswith("%") else float(text)
    except ValueError:
        raise UsageError(f"--speed-override: expected a percentage such as 50%, got {text!r}") from None
    if not (math.isfinite(value) and 0 < value <= 1):
        raise UsageError(f"--speed-override must be above 0% and at most 100%, got {text!r}")
    return value


def check(program: Any, path: str, registry: Any, attributes: Any = None, cell_world: Any = None) -> list[Diagnostic]:
    """The static checks (the one place the run command calls the checker); `attributes`: the world's soft and spatial
    ones; `cell_world`: the cell's world model, whose moving frames and external axes a program may name."""
    from orc_rpl.checking.checker import check_program

    from orc_rpl.transform.loading import moving_frames

    return check_program(program, path, registry, attributes, None if cell_world is None else moving_frames(cell_world))


def _fail_usage(message: str) -> int:
    sys.stderr.write(f"orc run: error: {message}\n")
    return 2


def run(args: argparse.Namespace) -> int:
    from orc_rpl.application.standard_behaviour import runtime_registry
    from orc_rpl.robot.robots import ROBOTS
    from orc_rpl.robot.servo_plants import servo_plant_spec
    from orc_rpl.syntax.files import declared_world, is_offline
    from orc_rpl.transform.loading import load_program_and_attributes
    from orc_rpl.transform.overrides import override_constants

    try:
        watch_how = watching(args)
        override = speed_override(args.speed_override)
        bus_robot.check_options(args)
        if args.port is not None and args.margins:
            raise UsageError("--margins: only a run on the simulated cell measures its margins")
        if args.port is not None and args.realtime:
            raise UsageError("--realtime: a real arm (--port) always runs in real time")
        if args.robot not in ROBOTS:
            raise UsageError(f"--robot: unknown robot {args.robot!r}; known robots: {', '.join(ROBOTS.names())}")
        if args.world is not None and not Path(args.world).is_dir() and not Path(args.world).is_file():
            raise UsageError(f"--world: '{args.world}' is neither a directory nor a world model file")
        check_outputs({"FILE": args.file, "--world": args.world},
                      {"--log": args.log, "--plot": args.plot, "--summary-json": args.summary_json})
        # An off-line program (.orl) runs as its on-line form; --world FILE (or its `# world:` line) names its world model.
        world_file = args.world if args.world is not None and Path(args.world).is_file() else None
        if args.world is None and not is_offline(args.file):
            world_file = _declared_cell(args.file)  # an on-line program's `-- world: FILE` line names its cell
        source, program, attributes = load_program_and_attributes(args.file, world_file)
        program = override_constants(program, args.set)
        cell = cell_world = None
        if args.port is None and not is_offline(args.file):
            cell, cell_world = world_cell(world_file, args.robot)
        elif args.port is None:  # an off-line program whose world has a track or a positioner runs in that world's cell
            offline_world = world_file or declared_world(args.file, source)
            cell, cell_world = world_cell(None if offline_world is None else str(offline_world), args.robot,
                                          only_moving=True)
        if args.port is None and args.plant == "elastic-gears":   # said before the program is checked for this robot
            check_elastic_gears(cell.robot if cell is not None else args.robot, "--plant elastic-gears")
    except UsageError as error:
        return _fail_usage(str(error))
    except SourceError as error:
        sys.stderr.write(error.format() + "\n")
        return 2
    except OrcError as error:  # an off-line program its world model cannot map
        return _fail_usage(str(error))
    registry = runtime_registry()
    diagnostics = check(program, args.file, registry, attributes, cell_world)
    if args.port is not None:
        diagnostics += bus_robot.torque_diagnostics(program, args.file, args.robot)
    elif cell is None and servo_plant_spec(args.robot) is not None and args.plant != "ideal":
        # the realistic plant of an arm on bus servos measures what the real one does: no joint torque
        diagnostics += bus_robot.torque_diagnostics(program, args.file, args.robot,
                                                    hint="--plant ideal runs it on the controller's own model")
    if diagnostics:
        for diagnostic in capped(diagnostics):
            sys.stderr.write(diagnostic.format(source) + "\n")
        sys.stderr.write(f"orc run: {len(diagnostics)} check error{'s' if len(diagnostics) != 1 else ''}; nothing moved\n")
        return 2
    try:
        return _run(args, source, program, registry, override, attributes, watch_how, cell, cell_world)
    except UsageError as error:
        return _fail_usage(str(error))
    except OrcError as error:
        sys.stderr.write(f"orc run: error: {error}\n")
        return 1
    except Exception as error:  # a bug of ours: say so, without a traceback
        sys.stderr.write(f"orc run: internal error (a bug in orc_rpl, please report it): {type(error).__name__}: {error}\n")
        return 1


def world_cell(world_file: str | None, robot: str, only_moving: bool = False) -> tuple[Any, Any]:
    """The simulated cell made from the world model `world_file` (contacts on) and that world when it has moving frames
    (a track, a positioner, a conveyor), read once; (None, None) without a world, and with `only_moving` when it has
    none. An off-line program runs in the default cell unless its world moves: the tools its worlds hang on the flange
    would meet the fixtures its bare-flange positions lead to (see docs/robots.md)."""
    if world_file is None:
        return None, None
    from orc_rpl.plant.world_scene import cell_from_world
    from orc_rpl.world import load_world

    world = load_world(world_file)
    moving = world if world.moving_frames() else None
    if only_moving and moving is None:
        return None, None
    model = world.robot.model if world.robot is not None else robot
    if robot not in ("irb2400", model):  # --robot's default gives way to the world's robot
        raise UsageError(f"--robot {robot} differs from the robot of the world model '{world_file}' ({model})")
    return cell_from_world(world, model), moving


def _declared_cell(path: str) -> str | None:
    from orc_rpl.syntax.files import declared_world
    from orc_rpl.syntax.reading import read_text

    try:
        text = read_text(path, "program")
    except OrcError:
        return None  # reading the program reports it
    cell = declared_world(path, text)
    return None if cell is None else str(cell)


def _watched(args: argparse.Namespace, executive: Any, robot: Any, program: Any, registry: Any, how: Any) -> Any:
    """The view and video around the run (view/), or nothing."""
    if how is None:
        return contextlib.nullcontext()
    from orc_rpl.view.watch import watch, world_of

    return watch(executive, robot, program, world_of(args.file, args.world), registry, how)


def _run(args: argparse.Namespace, source: str, program: Any, registry: Any, override: float, attributes: Any,
         watch_how: Any = None, cell: Any = None, cell_world: Any = None) -> int:
    from orc_rpl.executive.process_report import SIGNAL_UNITS, plotted_signals, submit_process_signals
    from orc_rpl.executive.report import Progress, summary, write_summary_text
    from orc_rpl.executive.cell_robot import CellRobot
    from orc_rpl.executive.executive import Executive
    from orc_rpl.executive.margins import MarginWatch, margin_lines
    from orc_rpl.executive.machine import Options
    from orc_rpl.executive.sim_io import load_script

    record = bool(args.log or args.plot)
    paced = args.realtime or (args.view and not args.fast)
    if args.port is not None:
        robot = bus_robot.connect(args, record)
    else:
        name = cell.robot if cell is not None else args.robot
        robot = CellRobot.virtual(robot=name, realtime=paced, record=record, plant=simulated_plant(args, name),
                                  seed=simulated_seed(args), cell=cell)
        robot.sensors.allow_devices = args.allow_devices  # a simulated run touches no device unless asked
        if cell_world is not None:
            robot.attach_world(cell_world)  # its tracks and positioners move with the arm

    def out(line: str) -> None:
        try:
            sys.stdout.write(line + "\n")
            sys.stdout.flush()
        except BrokenPipeError:  # `orc run F | head`: the reader went away; the run goes on, its output is dropped
            quiet_stdout()

    executive = Executive(program, robot, registry, path=args.file, source=source, output=out,
                          options=Options(speed_override=override, world_attributes=attributes, cell_world=cell_world,
                                          statement_budget=args.statement_budget or None))
    machine = executive.machine
    machine.on_warning = lambda span, message: sys.stderr.write(f"{args.file}:{span.line}:{span.column}: warning: {message}\n")
    # the run's process record; with --log/--plot, the tool's TCP and the process signals beside the flange
    submit_process_signals(robot.layer.logger if record else None, robot, lambda: machine.last_tool)
    io_script = equipment_script(args, args.file, args.world)
    if io_script is not None:
        load_script(io_script, robot.io, lambda: robot.plant_tcp_pose(machine.last_tool), robot.set_plant_payload,
                    robot.push_on_arm)
    margins = MarginWatch(robot, machine) if args.margins else None
    # what watches the run listens to the robot's motion cycles while it runs: the executive drives the robot itself
    with Progress(executive, sys.stderr, PROGRESS_EVERY_TICKS, robot), margins or contextlib.nullcontext(), \
            _watched(args, executive, robot, program, registry, watch_how) as watchers:
        if watchers is not None:
            watchers.monitor(robot)
        wall_start = time.perf_counter()  # after the view's page connected
        with paced_priority(paced, "orc run"), session_priority(args.view and args.fast and args.port is None, "orc run"):
            interrupted = _run_until_done(executive, args.timeout, simulated=args.port is None)
    if interrupted and args.port is not None:
        bus_robot.stop_and_hold(robot)  # a real arm brakes, then holds with torque on (it must not fall)
    elif interrupted:
        stop_on_path(robot)
    wall_s = time.perf_counter() - wall_start
    result = summary(executive, robot)
    if executive.status == "failed":
        sys.stderr.write(executive.report() + "\n")
    if interrupted:
        result["status"], result["interrupted_by"] = "interrupted", interrupted
        where = "the arm holds its position" if args.port is not None else "the robot stopped on its path"
        sys.stderr.write(f"orc run: interrupted by {interrupted}; {where}\n")
    if margins is not None:
        result["margins"] = margins.section(args.file)
    write_summary_text(result, wall_s, sys.stderr, real_arm=args.port is not None)
    for line in margin_lines(result.get("margins")):
        sys.stderr.write(f"margins: {line}\n")
    try:
        if args.summary_json:
            write_text_atomic(args.summary_json, json.dumps(result, indent=2) + "\n")
        if record and robot.layer.logger is not None:
            recording = robot.layer.logger.recording()
            if args.log:
                recording.to_npz(args.log)
            if args.plot:
                recording.plot_png(args.plot, signals=plotted_signals(recording), tcp="tool_tcp",
                                   title=f"orc run {Path(args.file).name}", units=SIGNAL_UNITS)
    except OSError as error:  # the folders were checked before the run; a full disk still fails here
        sys.stderr.write(f"orc run: error: cannot write '{error.filename}': {error.strerror}\n")
        return 1
    if watchers is not None:
        watchers.linger()  # at a terminal, the 3D view stays open until Enter
    if interrupted in INTERRUPT_EXIT_CODES:
        return INTERRUPT_EXIT_CODES[interrupted]
    return 1 if executive.status == "failed" or interrupted else 0


@contextlib.contextmanager
def paced_priority(paced: bool, command: str, tell_refusal: Callable[[str], Any] | None = None) -> Iterator[None]:
    """A command paced to the wall clock (`orc run --view`, `orc pendant --view`) runs its motion cycle at real-time
    priority (motion/scheduling.py's safeguards), or says why it cannot (to `tell_refusal`, else on stderr); when
    the runaway guard put the cycle back to normal priority, it says so on stderr at the end."""
    if not paced:
        yield
        return
    priority = scheduling.PacedPriority()
    with priority:
        if priority.refused is not None:
            refusal = (f"{command}: the motion cycle runs at normal priority: {priority.refused}; other busy programs "
                       "on this machine (a browser drawing the view) can make it late")
            (tell_refusal or _stderr_line)(refusal)
        yield
    if priority.demoted:
        _stderr_line(f"{command}: the motion cycle computed {scheduling.RUNAWAY_CPU_S:g} s without waiting at "
                     "real-time priority; it went on at normal priority")


@contextlib.contextmanager
def session_priority(drawn: bool, command: str) -> Iterator[None]:
    """A run drawn in a browser but not paced (`orc run --view --fast`) runs its session at a higher priority than
    the browser's (motion/scheduling.py's SessionPriority), or says why it cannot."""
    if not drawn:
        yield
        return
    with scheduling.SessionPriority() as priority:
        if priority.refused is not None:
            _stderr_line(f"{command}: the run keeps its priority: {priority.refused}; a browser drawing the view on "
                         "this machine can slow the run")
        yield


def _stderr_line(text: str) -> None:
    sys.stderr.write(text + "\n")


#: The shell's codes of a program a signal stopped (128 + SIGINT, 128 + SIGTERM): the run ended as the signal asked,
#: its summary and log written.
INTERRUPT_EXIT_CODES = {"Ctrl-C": 130, "SIGTERM": 143}


class Terminated(KeyboardInterrupt):
    """SIGTERM during a run (`kill`, `timeout`, a supervisor): stopped as Ctrl-C stops it, so the robot stops on its
    path and the summary, the log and the plots are still written (and the session's priority put back)."""


@contextlib.contextmanager
def _terminated_as_interrupt() -> Iterator[None]:
    """SIGTERM raises `Terminated` in the run's thread until the block ends (where this is the main thread)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def terminate(signum: int, frame: Any) -> None:
        raise Terminated()

    previous = signal.signal(signal.SIGTERM, terminate)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def _run_until_done(executive: Any, timeout_s: float | None, simulated: bool = True) -> str:
    """Run the program; what interrupted it ("Ctrl-C", the timeout) or "" when it ended by itself."""
    limit = TimeLimit(executive.machine.robot, timeout_s, executive) if timeout_s is not None else None
    try:
        with limit or contextlib.nullcontext(), _terminated_as_interrupt():
            executive.run()
    except Terminated:
        return "SIGTERM"
    except KeyboardInterrupt:
        return "Ctrl-C"
    if limit is not None and limit.reached and executive.status == "paused":
        return f"--timeout {timeout_s:g} s" + (" (simulated)" if simulated else "")
    return ""


def add_cell_options(parser: argparse.ArgumentParser) -> None:
    """--allow-devices, --plant, --seed and --sim: what the simulated cell is made of (orc run and orc pendant)."""
    parser.add_argument("--allow-devices", action="store_true",
                        help="let the program open the serial devices its PORT attributes name (default: none is opened)")
    parser.add_argument("--plant", choices=SIMULATED_PLANTS, default=None,
                        help="realistic: friction, motor heat, encoders, masses off the model, rigid gears (default); "
                             "elastic-gears: the same with elastic gears under the gears' feed-forward and the state "
                             "feedback (IRB 2400; moves from rest take longer: "
                             "docs/robots.md, 'Which plant'); ideal: the controller's own model, exactly "
                             "(simulation only: not with --port)")
    # No default here, so that a real arm (--port) can refuse a seed it would not use; a simulated cell reads
    # it through simulated_seed.
    parser.add_argument("--seed", metavar="N", type=int, default=None,
                        help="seed of the plant's noise (default 0; simulation only: not with --port)")
    parser.add_argument("--sim", metavar="FILE.sim.yaml",
                        help="the simulated equipment (IO events, weld guns, parts, castings, seam) instead of the "
                             "program's own <name>.sim.yaml: a variation of the cell (simulation only)")


def simulated_seed(args: argparse.Namespace) -> int:
    """The seed of the simulated plant's noise: --seed, else 0."""
    return 0 if args.seed is None else args.seed


def equipment_script(args: argparse.Namespace, program: str | None, world_dir: str | None) -> Path | None:
    """The simulated equipment of a run: --sim FILE, else the program's <name>.sim.yaml (in world_dir or beside it)."""
    from orc_rpl.executive.sim_io import script_path

    if args.sim is not None:
        return Path(args.sim)
    return None if program is None else script_path(program, world_dir)


def simulated_plant(args: argparse.Namespace, robot: str) -> str:
    """--plant, or the robot's default: realistic where it has a plant description (said when it has none)."""
    from orc_rpl.robot.plants import PLANTS, default_plant
    from orc_rpl.robot.servo_plants import SERVO_PLANTS

    if args.plant == "elastic-gears":
        check_elastic_gears(robot, "--plant elastic-gears")
    if args.plant is not None:
        return str(args.plant)
    plant = default_plant(robot)
    if plant != "realistic":
        sys.stderr.write(f"orc: robot {robot!r} has no realistic plant description yet "
                         f"(robots with one: {', '.join(sorted([*PLANTS, *SERVO_PLANTS]))}): running on the ideal plant\n")
    return plant
