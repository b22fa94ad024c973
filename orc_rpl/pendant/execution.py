"""The pendant's execution controller: the executive behind it, modes and settings, and the jobs that move the robot."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np

from orc_rpl.checking.checker import check_in_context
from orc_rpl.errors import OrcError, SourceError
from orc_rpl.executive.executive import Executive
from orc_rpl.executive.machine import Options
from orc_rpl.executive.motions import resolve_tool
from orc_rpl.executive.signals import RunError
from orc_rpl.pendant.adapter import point_at, prepare, statement_steps
from orc_rpl.pendant.editing import Editor, joints_text, number_text, pose_text
from orc_rpl.pendant.events import EventLog
from orc_rpl.pendant.robot import PendantRobot
from orc_rpl.pendant.tree import EditError
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.parser import parse_statement
from orc_rpl.transform.loading import moving_frames
from orc_rpl.world.pose import Pose

#: A synchronous session lets a job run this many motion cycles at most (an hour at 4 ms).
SYNC_LIMIT_TICKS = 900_000


class Execution:
    """Owns the executive of the editor's program, the tool, override and mode, and the one job that runs.

    `synchronous=True` (tests, scripts) runs each job to its end in simulated time before a command returns;
    the terminal application passes False and advances time with `pump()`.
    """

    def __init__(self, editor: Editor, robot: PendantRobot, registry: object, events: EventLog,
                 synchronous: bool = True, on_print: Callable[[str], None] | None = None, mode: str = "manual") -> None:
        self.editor = editor
        self.robot = robot
        self.registry = registry
        self.events = events
        self.synchronous = synchronous
        self.on_print = on_print
        self.tool = "ARM"
        self.override = 1.0
        self.mode = mode
        self.printed: list[str] = []            #: every PRINT of the session
        self.notices: list[str] = []            #: what the running job reported and the screen has not shown yet
        self.job: Iterator[object] | None = None
        self.job_name = ""
        self._ex: Executive | None = None
        self._ex_dirty = True
        self._slice_ticks = SYNC_LIMIT_TICKS
        self._sliced = False
        robot.set_mode(mode)
        editor.on_change.append(self._program_changed)
        cell_world = _cell_world(robot)
        if cell_world is not None:  # the checks know the cell's moving frames, as orc check --world does
            editor.moving_frames = moving_frames(cell_world)

    def _program_changed(self) -> None:
        self._ex_dirty = True

    # -- the executive ------------------------------------------------------------------------

    def executive(self) -> Executive:
        """The executive of the current program, its names given values; rebuilt after an edit, keeping the pointer
        on the same statement when it is still there."""
        if self._ex is not None and (not self._ex_dirty or self.job is not None):
            return self._ex  # a running job keeps its executive; the edited program is compiled when it ends
        editor = self.editor
        old = self._ex
        keep = old.pointer.statement if old is not None and old.pointer is not None and old.status == "paused" else None
        ex = Executive(editor.program, self.robot, self.registry, path=str(editor.path), source=editor.text,
                       output=self._print, options=Options(speed_override=self.override, cell_world=_cell_world(self.robot)))
        ex.tracing = True  # the pointer follows every statement, so :stop can stop anywhere
        self._ex, self._ex_dirty = ex, False
        for failure in prepare(ex, editor.program):
            self.notify(failure.report(str(editor.path), editor.text))
        target = next((s for s in editor.stops if keep is not None and s.statement == keep and not s.end
                       and s.routine is None), None)
        if target is not None:
            point_at(ex, editor.program, target)
        else:
            self.restart(ex)  # the pointer shows the first statement, as on a freshly loaded program
        return ex

    @property
    def pointer_line(self) -> int | None:
        """The line of the statement the program pointer is before (None: at the end, or not started)."""
        ex = self.executive()
        return ex.pointer.line if ex.pointer is not None and ex.status == "paused" else None

    def _print(self, line: str) -> None:
        self.printed.append(line)
        self.notices.append(line)
        if self.on_print is not None:
            self.on_print(line)

    def notify(self, text: str) -> None:
        """A job's report: shown on the screen and logged (its first line)."""
        self.notices.append(text)
        self.events.record(text.splitlines()[0] if text else text)

    def tool_pose(self) -> Pose | None:
        if self.tool == "ARM":
            return None
        return resolve_tool(self.executive().machine.globals.get(self.tool))

    def current_pose_text(self, frame: str) -> str:
        """The TCP of the pendant's tool, relative to `frame`, as RPL text (after the robot came to rest)."""
        self.robot.run_until_idle()
        try:
            frame_world = self.executive().machine.frame_matrix(frame)
        except RunError as error:
            raise EditError(f"cannot teach relative to FRAME {frame}: {error.message}") from None
        world = self.robot.commanded_tcp(self.tool_pose())
        relative = Pose.from_matrix(np.linalg.inv(frame_world) @ world.matrix(), frame)
        return axes_text(pose_text(relative), self.robot) + (f" IN {frame}" if frame != "world" else "")

    def current_joints_text(self) -> str:
        """The commanded joints as a JOINTS(...) literal (after the robot came to rest)."""
        self.robot.run_until_idle()
        return joints_text(tuple(self.robot.layer.reference_q()))

    # -- settings -----------------------------------------------------------------------------

    def set_tool(self, name: str) -> str:
        if name != "ARM":
            declared = self.editor.declared().get(name)
            if not isinstance(declared, (n.Declaration, n.Install)) or (isinstance(declared, n.Declaration) and declared.kind != "TOOL"):
                raise EditError(f":tool {name}: not a declared TOOL (ARM is the bare flange)")
            try:
                resolve_tool(self.executive().machine.globals.get(name))
            except RunError as error:
                raise EditError(f":tool {name}: {error.message}") from None
        self.tool = name
        return self.events.record(f"tool {name}")

    def set_override(self, fraction: float) -> str:
        if not 0 < fraction <= 1:
            raise EditError(f":override must be above 0% and at most 100%, got {fraction * 100:g}%")
        self.override = fraction
        if self._ex is not None:
            self._ex.machine.options.speed_override = fraction
        return self.events.record(f"speed override {fraction * 100:g}%")

    def set_mode(self, mode: str) -> str:
        if mode not in ("manual", "auto"):
            raise EditError(f":mode: expected manual or auto, got {mode!r}")
        self.mode = mode
        self.robot.set_mode(mode)
        cap = " (TCP speed capped at 250 mm/s, program motions included)" if mode == "manual" else ""
        return self.events.record(f"mode {mode}{cap}")

    # -- jobs -----------------------------------------------------------------------------------

    @property
    def busy(self) -> bool:
        return self.job is not None

    def refuse_if_busy(self) -> None:
        """An EditError while a job runs: one motion source at a time."""
        if self.job is not None:
            raise EditError(f"busy: {self.job_name} is running (:stop stops it)")

    def start(self, name: str, job: Iterator[object]) -> str:
        """Make `job` the running job; a synchronous session runs it to its end here."""
        self.refuse_if_busy()
        self.job, self.job_name = job, name
        self.notices = []
        if not self.synchronous:
            self.pump(1)
            return f"{name} ..." if self.job is not None else "\n".join(self.notices)
        self.pump(SYNC_LIMIT_TICKS)
        if self.job is not None:
            self.stop()
            self.notify(f"{name}: still running after {SYNC_LIMIT_TICKS} motion cycles; stopped")
        self.robot.run_until_idle()
        return "\n".join(self.notices)

    def pump(self, max_ticks: int) -> None:
        """Advance the running job (or the jog motions) by up to `max_ticks` motion cycles."""
        robot, editor = self.robot, self.editor
        self._slice_ticks = max(1, max_ticks)
        start = robot.ticks
        while self.job is not None and robot.ticks - start < max_ticks:
            try:
                next(self.job)
            except StopIteration:
                self.job = None
            except RunError as error:
                self.job = None
                self.notify(error.report(str(editor.path), editor.text))
            except OrcError as error:
                self.job = None
                self.notify(f"{self.job_name}: {error}")
            except Exception as error:  # a bug of ours: reported, never a traceback in the terminal
                self.job = None
                self.notify(f"internal error (a bug in orc_rpl, please report it): {type(error).__name__}: {error}")
        while self.job is None and robot.pending() > 0 and robot.ticks - start < max_ticks:
            robot.tick()

    def _slice(self) -> None:
        self._sliced = True
        if self._ex is not None:
            self._ex.pause()

    def _drive(self, name: str, how: Callable[[Executive], str]) -> str:
        ex = self.executive()
        if ex.finished or ex.pointer is None:
            self.restart(ex)
        robot = self.robot
        robot.line_source = lambda: ex.pointer.line if ex.pointer is not None else 0

        def job() -> Iterator[object]:
            while True:
                self._sliced = False
                robot.slice_end, robot.on_slice_end = robot.ticks + self._slice_ticks, self._slice
                try:
                    status = how(ex)
                finally:
                    robot.slice_end = None
                if status == "paused" and self._sliced:
                    yield None
                    continue
                self._finished(ex, status)
                return
        return self.start(name, job())

    def restart(self, ex: Executive) -> None:
        """The program pointer to the first statement of the main program."""
        top = next((s for s in self.editor.stops if not s.body), None)
        if top is not None:
            point_at(ex, self.editor.program, top)

    def _finished(self, ex: Executive, status: str) -> None:
        if status == "failed":
            self.notify(ex.report())
        elif status == "paused":
            self.notify(f"paused before line {ex.pointer.line}")
            self.editor.goto(ex.pointer.line, quiet=True)
        else:
            self.notify(f"program {status}")

    # -- the commands -------------------------------------------------------------------------

    def run(self) -> str:
        """Run from the program pointer to the end (or a STOP, an error, :stop)."""
        return self._drive("run", lambda ex: ex.run())

    def step(self) -> str:
        """Run the statement at the program pointer (calls included) and stop before the next one."""
        return self._drive("step", lambda ex: ex.step_over())

    def stop(self) -> str:
        """Stop the robot on its path; a stopped program motion runs again from where the robot stands on :run."""
        was = self.job_name if self.job is not None else None
        if self.job is not None:
            self.job.close()
            self.job = None
        self.robot.halt()
        ex = self._ex
        if was in ("run", "step") and ex is not None and ex.pointer is not None and ex.pointer.depth == 1:
            again = next((s for s in self.editor.stops if s.line == ex.pointer.line and not s.end and s.routine is None), None)
            if again is not None:
                point_at(ex, self.editor.program, again)
        return self.events.record(f"stopped{f' ({was})' if was else ''}")

    def execute_text(self, text: str) -> str:
        """A statement typed at the command line, executed at once in the cursor's context (its FRAME block)."""
        try:
            stmt = parse_statement(text, "<typed>")
        except SourceError as error:
            raise EditError(error.format()) from None
        routine, frame = self.editor.context()
        # checked where it will run, so an error points at the offending word before anything moves
        problems = check_in_context(self.editor.program, stmt, routine, frame, "<typed>", self.registry,
                                    self.executive().machine.globals, self.editor.moving_frames)
        if problems:
            raise EditError("\n".join(problem.format(text) for problem in problems))
        return self.statement_job("typed", stmt, routine, frame, 0, text)

    def exec_cursor(self) -> str:
        """Execute the statement under the cursor in its lexical context: its FRAME block and its scope."""
        stop = self.editor.at_cursor
        if stop.end:
            raise EditError(":exec: the cursor is on an END line; move it to a statement")
        return self.statement_job("exec", stop.statement, stop.routine, stop.frame, stop.line, None)

    def statement_job(self, name: str, stmt: n.Statement, routine: str | None, frame: str,
                      line: int, typed: str | None, quiet: bool = False) -> str:
        """Run one statement in a given routine scope and FRAME context as the job `name`."""
        ex = self.executive()
        editor = self.editor
        self.robot.line_source = lambda: line

        def job() -> Iterator[object]:
            try:
                yield from statement_steps(ex, stmt, routine, frame)
            except RunError as error:
                self.notify(error.report("<typed>", typed) if typed is not None else error.report(str(editor.path), editor.text))
                return
            if not quiet:
                where = f" in FRAME {frame}" if frame != "world" else ""
                self.notify(f"done{where}: {(typed or editor.text.splitlines()[line - 1]).strip().splitlines()[0]}")
        return self.start(name, job())


def axes_text(pose: str, robot: Any) -> str:
    """A taught pose with the cell's external axes where they are commanded to be: `AXES(POSE(...), turn = 90deg)`."""
    cell_axes = getattr(getattr(robot, "cell", None), "axes", None)
    if cell_axes is None or cell_axes.external is None:
        return pose
    world = cell_axes.world
    values = [f"{name} = " + (number_text(math.degrees(v), "deg", 3) if world.object(name).axis.rotary
                                else number_text(v * 1000.0, "mm", 3)) for name, v in cell_axes.external.planned.items()]
    return f"AXES({pose}, {', '.join(values)})"


def _cell_world(robot: Any) -> Any:
    """The cell's world model when it has moving frames (programs may name them), else None."""
    cell_axes = getattr(getattr(robot, "cell", None), "axes", None)
    return None if cell_axes is None else cell_axes.world
