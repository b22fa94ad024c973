"""The executive's state shared by all compiled code: globals, call stack, frames, the robot, IO and time."""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from orc_rpl.application.registry import Registry
from orc_rpl.application.runtime import RobotInterface
from orc_rpl.errors import MotionFault, OrcError
from orc_rpl.executive.signals import ReturnSignal, RunError, StackEntry
from orc_rpl.executive.values import IOBank, type_name
from orc_rpl.syntax.nodes import Span
from orc_rpl.world.pose import Pose

#: A run-time stand-in for "one motion cycle passed": yielded by statements that wait.
TICK = object()

#: The cell's names of the language's IO banks (plant.io.CellIO).
CELL_BANKS = {"DigIn": "DigIn", "DigOut": "DigOut", "AnalogIn": "AnaIn", "AnalogOut": "AnaOut"}


@dataclass(slots=True)
class Activation:
    """One call of a routine: its name, where it was called from and its local variables."""

    routine: str
    call_span: Span | None
    locals: dict[str, Any]


@dataclass(slots=True)
class Outstanding:
    """A blended motion still running while the program goes on: checked for faults later."""

    ticket: Any
    span: Span
    stack: tuple[StackEntry, ...]


@dataclass(slots=True)
class Options:
    """How a run behaves beyond the program text."""

    max_depth: int = 200                       #: routine calls deeper than this are an error
    speed_override: float = 1.0                #: `--speed-override`, scales every speed
    idle_wait_limit_s: float | None = 3600.0   #: a WAIT UNTIL without TIMEOUT gives up after this (None: never)
    #: the world's soft and spatial attributes, object -> name -> value (`pallet.next_row`), read by programs
    world_attributes: Mapping[str, Mapping[str, Any]] = field(default_factory=dict)
    statement_budget: int | None = 1_000_000   #: statements in a row without simulated time passing (None: no limit)
    #: the cell's world model when it has moving frames (tracks, positioners): frames a program may name
    cell_world: Any = None


class Machine:
    """Everything compiled statements read and change; one per run."""

    def __init__(self, robot: RobotInterface, registry: Registry, output: Callable[[str], None],
                 options: Options | None = None) -> None:
        self.robot = robot
        self.registry = registry
        self.output = output
        self.options = options or Options()
        self.globals: dict[str, Any] = {}
        self.consts: set[str] = set()
        self.frames: dict[str, Pose] = {}              #: FRAME declarations, each relative to its parent frame
        self.stack: list[Activation] = [Activation("main", None, self.globals)]
        self.routines: dict[str, Any] = {}             #: name -> CompiledRoutine
        self.trace = False                             #: yield a program-pointer event before each statement
        self.last_tool: Pose | None = None             #: the tool last moved (HERE's TCP)
        self.motions = 0                               #: motion statements executed
        self.motion_span: Span | None = None           #: the motion statement submitting now (for watchers)
        self.executed = 0                              #: statements (and loop iterations) executed
        self._budget_at = (self.options.statement_budget or 0) or None  #: `executed` at the next budget check
        self._budget_time_s = -1.0                     #: simulated time at the last budget check
        self.outstanding: list[Outstanding] = []
        self.prints: list[str] = []
        self.warnings: list[tuple[Span, str]] = []    #: each (place, message) once
        self.on_warning: Callable[[Span, str], None] = lambda span, message: None

    def warn(self, message: str, span: Span) -> None:
        """A warning about a statement, reported the first time only."""
        if (span, message) not in self.warnings:
            self.warnings.append((span, message))
            self.on_warning(span, message)

    # -- the call stack ------------------------------------------------------------------

    def stack_entries(self) -> tuple[StackEntry, ...]:
        return tuple(StackEntry(a.routine, a.call_span.line if a.call_span else 0,
                                a.call_span.column if a.call_span else 0) for a in self.stack)

    def push(self, routine: str, span: Span, local_values: dict[str, Any]) -> Activation:
        if len(self.stack) > self.options.max_depth:
            raise RunError(f"calls nested deeper than {self.options.max_depth} (endless recursion in {routine}?)")
        activation = Activation(routine, span, local_values)
        self.stack.append(activation)
        return activation

    def pop(self) -> None:
        self.stack.pop()

    def call_now(self, routine: Any, args: list[Any], span: Span) -> Any:
        """Call a routine to completion from inside an expression (motions in it run; no stepping inside)."""
        local_values = routine.bind(args)
        self.push(routine.name, span, local_values)
        try:
            if routine.fast is not None and not self.trace:
                routine.fast(local_values)
            else:
                for _ in routine.gen(local_values):
                    pass
        except ReturnSignal as result:
            return result.value
        finally:
            self.pop()
        if routine.kind == "FUNC":
            raise RunError(f"FUNC {routine.name} ended without RETURN")
        return None

    # -- errors --------------------------------------------------------------------------

    def count(self) -> None:
        """One more statement or loop iteration; past the budget with no simulated time passed, a RunError."""
        self.executed += 1
        if self._budget_at is not None and self.executed >= self._budget_at:
            self._check_budget()

    def _check_budget(self) -> None:
        # Simulated time only passes while the robot is asked to move or wait: a loop that does neither never ends.
        budget = self.options.statement_budget or 0
        now_s = self.robot.time_s()
        if now_s > self._budget_time_s:
            self._budget_time_s = now_s
            self._budget_at = self.executed + budget
            return
        raise RunError(f"{budget} statements ran without the robot moving or time passing (an endless loop?); "
                       "`orc run --statement-budget N` changes the limit")

    def translate(self, error: BaseException, span: Span) -> RunError:
        """Any failure inside a statement as a located RunError (a bug of ours says so)."""
        if isinstance(error, RunError):
            return error.located(span, self.stack_entries())
        if isinstance(error, MotionFault):
            result = RunError(f"{error.rpl_name}: {error}", name=error.rpl_name)
        elif isinstance(error, OrcError):
            result = RunError(str(error))
        elif isinstance(error, ZeroDivisionError):
            result = RunError("division by zero")
        elif isinstance(error, RecursionError):
            result = RunError("calls nested too deeply (endless recursion?)")
        elif isinstance(error, (OverflowError, ValueError)):
            result = RunError(f"arithmetic error: {error}")
        else:
            result = RunError(f"internal error (a bug in orc_rpl, please report it): {type(error).__name__}: {error}")
        return result.located(span, self.stack_entries())

    # -- time and motion -----------------------------------------------------------------

    def tick(self) -> None:
        self.robot.tick()

    def sync(self) -> Iterator[object]:
        """Wait (yielding each motion cycle) until every motion has finished; report a blended motion's fault."""
        robot = self.robot
        while robot.pending() > 0:
            robot.tick()
            yield TICK
        self.check_outstanding()

    def sync_now(self) -> None:
        """`sync` without yielding, for expressions (HERE) that need the robot at rest."""
        for _ in self.sync():
            pass

    def check_outstanding(self) -> None:
        keep = []
        for item in self.outstanding:
            if item.ticket.outcome == "fault":
                self.outstanding = []
                error = self.translate(item.ticket.error, item.span)
                error.span, error.stack = item.span, item.stack
                raise error
            if not item.ticket.done:
                keep.append(item)
        self.outstanding = keep

    # -- frames --------------------------------------------------------------------------

    def moving_frame_of(self, frame: str) -> str | None:
        """The cell's moving frame an on-line frame hangs on (through its parents), or None."""
        moving = self.moving_frames()
        seen = 0
        while frame != "world" and seen <= 64:
            if frame in moving:
                return frame
            pose = self.frames.get(frame)
            if pose is None:
                return None
            frame, seen = pose.frame, seen + 1
        return None

    def moving_frames(self) -> tuple[str, ...]:
        world = self.options.cell_world
        return () if world is None else world.moving_frames()

    def axis_values(self) -> dict[str, float]:
        """Where the cell's external axes are now (empty without any)."""
        values = getattr(self.robot, "axis_values", None)
        return {} if values is None else values()

    def frame_matrix(self, frame: str, axis_values: dict[str, float] | None = None) -> np.ndarray:
        """World transform of an on-line frame (through its parents; a moving frame where its axis is, or at
        `axis_values`)."""
        chain = np.eye(4)
        seen = 0
        moving = self.moving_frames()
        while frame != "world":
            if frame in moving:
                world = self.options.cell_world
                values = self.axis_values() if axis_values is None else axis_values
                base_home = world.world_pose("robot").matrix()  # the program's world: the base with the axes at home
                return np.linalg.inv(base_home) @ world.with_axes(values).world_pose(frame).matrix() @ chain
            pose = self.frames.get(frame)
            if pose is None:
                raise RunError(f"'{frame}' is not a declared FRAME")
            chain = pose.matrix() @ chain
            frame = pose.frame
            seen += 1
            if seen > 64:
                raise RunError("FRAME declarations refer to each other in a circle")
        return chain

    def to_world(self, pose: Pose) -> Pose:
        if pose.frame == "world":
            return pose
        return Pose.from_matrix(self.frame_matrix(pose.frame) @ pose.matrix(), "world")

    def here(self, frame: str, in_motion: bool) -> Pose:
        """HERE: the TCP of the tool last moved, relative to `frame`."""
        if not in_motion:
            self.sync_now()
        world = self.robot.tcp_pose(self.last_tool)
        pose = world if frame == "world" else Pose.from_matrix(np.linalg.inv(self.frame_matrix(frame)) @ world.matrix(), frame)
        # below a picometre and a picoradian is rounding noise of the transforms: PRINT HERE.z shows 0.2 m, not 0.19999999999999996 m
        world_model = self.options.cell_world
        axes = () if world_model is None else tuple(sorted(
            (k, round(v, 12) + 0.0) for k, v in self.axis_values().items() if world_model.object(k).axis.joint != "conveyor"))
        return Pose(*(round(v, 12) + 0.0 for v in (pose.x, pose.y, pose.z, pose.a, pose.b, pose.c)), frame=pose.frame, axes=axes)

    # -- IO --------------------------------------------------------------------------------

    def read_io(self, bank: IOBank, number: Any) -> Any:
        channels = self.robot.io.bank(CELL_BANKS[bank.name])
        value = channels[_channel(bank, number)]
        return int(value) if bank.digital else float(value)

    def write_io(self, bank: IOBank, number: Any, value: Any) -> None:
        if not bank.output:
            raise RunError(f"{bank.name} is an input: it cannot be assigned")
        channels = self.robot.io.bank(CELL_BANKS[bank.name])
        if bank.digital:
            if value not in (0, 1) or not isinstance(value, (int, float, bool)):
                raise RunError(f"{bank.name}[{number}] is digital: assign 0/1 or TRUE/FALSE, not {type_name(value)}")
            channels[_channel(bank, number)] = bool(value)
        else:
            if type(value) not in (int, float):
                raise RunError(f"{bank.name}[{number}] takes a number (volts), not {type_name(value)}")
            channels[_channel(bank, number)] = float(value)


def _channel(bank: IOBank, number: Any) -> int:
    if type(number) is float and number == int(number):
        number = int(number)
    if type(number) is not int:
        raise RunError(f"{bank.name}[...] needs a whole channel number, got {type_name(number)}")
    return number


@dataclass(slots=True)
class CompiledRoutine:
    """A PROC or FUNC compiled once: its body as a generator (and a plain function when it never waits)."""

    name: str
    kind: str
    params: tuple[str, ...]
    gen: Callable[[dict[str, Any]], Iterator[object]] | None = None
    fast: Callable[[dict[str, Any]], None] | None = None
    suspends: bool = True
    extra: dict[str, Any] = field(default_factory=dict)

    def bind(self, args: list[Any]) -> dict[str, Any]:
        if len(args) != len(self.params):
            raise RunError(f"{self.kind} {self.name} takes {len(self.params)} argument"
                           f"{'s' if len(self.params) != 1 else ''}, got {len(args)}")
        return dict(zip(self.params, args))

