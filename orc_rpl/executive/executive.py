"""The executive: runs a compiled program as one generator; program pointer, stepping, breakpoints, pause, exec in context."""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

from orc_rpl.application.registry import Registry
from orc_rpl.application.runtime import RobotInterface
from orc_rpl.application.standard_behaviour import runtime_registry
from orc_rpl.errors import SourceError
from orc_rpl.executive.blocks import make_block
from orc_rpl.executive.machine import TICK, Machine, Options
from orc_rpl.executive.scope import Scope, analyse, nested_bodies
from orc_rpl.executive.signals import ReturnSignal, RunError, StackEntry, StopSignal
from orc_rpl.executive.statements import StatementCompiler
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.parser import parse_statement

#: How long (simulated) a failed run lets the robot decelerate on its path.
STOP_TIMEOUT_S = 10.0


@dataclass(frozen=True, slots=True)
class ProgramPointer:
    """The statement about to run and the calls that lead to it (outermost first)."""

    statement: n.Statement
    line: int
    column: int
    routine: str                          #: "main" or the routine the statement is in
    call_stack: tuple[StackEntry, ...]    #: main first; each entry's line/column is its call site

    @property
    def depth(self) -> int:
        return len(self.call_stack)


class Executive:
    """Runs one program on one robot. `run()` to the end (or a breakpoint or pause); `step_into()`,
    `step_over()`, `step_out()` stop at the next statement; `execute(text)` runs one statement in the
    lexical context of the program pointer. Status: ready, paused, finished, stopped or failed."""

    def __init__(self, program: n.Program, robot: RobotInterface, registry: Registry | None = None,
                 path: str = "<program>", source: str | None = None, output: Callable[[str], None] | None = None,
                 options: Options | None = None) -> None:
        self.path, self.source = path, source
        self.machine = Machine(robot, registry or runtime_registry(), output or (lambda line: print(line)), options)
        self.scopes = analyse(program)
        self.compiler = StatementCompiler(self.machine, self.scopes)
        for name, routine in self.scopes.routines.items():
            self.machine.routines[name] = self.compiler.declarations.routine(routine)
        self.main = self.compiler.block(program.body, Scope())
        self.contexts: dict[int, tuple[str | None, str]] = {}   #: line -> (routine, FRAME) of the statement there
        self.statements: dict[int, n.Statement] = {}            #: line -> the (first) statement starting there
        self._record_contexts(program.body, None, "world")
        self.breakpoints: set[int] = set()
        self.tracing = False              #: yield at every statement even without breakpoints (the pendant sets it)
        self.status = "ready"
        self.pointer: ProgramPointer | None = None
        self.error: RunError | None = None
        self._gen: Iterator[object] | None = None
        self._pause = False

    # -- the program's lexical contexts ---------------------------------------------------

    def _record_contexts(self, body: n.Body, routine: str | None, frame: str) -> None:
        for stmt in body:
            if isinstance(stmt, (n.Comment, n.Blank)):
                continue
            self.contexts.setdefault(stmt.span.line, (routine, frame))
            self.statements.setdefault(stmt.span.line, stmt)
            if isinstance(stmt, n.Routine):
                self._record_contexts(stmt.body, stmt.name.id, "world")
            elif isinstance(stmt, n.FrameBlock):
                self._record_contexts(stmt.body, routine, stmt.frame.id)
            else:
                self._record_contexts(nested_bodies(stmt), routine, frame)

    # -- running ---------------------------------------------------------------------------

    @property
    def robot(self) -> RobotInterface:
        return self.machine.robot

    @property
    def finished(self) -> bool:
        return self.status in ("finished", "stopped", "failed")

    def _program(self) -> Iterator[object]:
        m = self.machine
        yield from self.main.gen(m.globals)
        yield from m.sync()  # the program ends when the robot has arrived

    def run(self) -> str:
        """Run until the program ends, a breakpoint is reached or pause() was called; returns the status."""
        return self._drive(lambda pointer: False)

    def step_into(self) -> str:
        """Run the statement at the pointer and stop at the next one, inside a called routine if any."""
        return self._drive(lambda pointer: True, stepping=True)

    def step_over(self) -> str:
        """Run the statement at the pointer, calls included, and stop at the next one at this depth or above."""
        depth = self.pointer.depth if self.pointer else 1
        return self._drive(lambda pointer: pointer.depth <= depth, stepping=True)

    def step_out(self) -> str:
        """Run to the first statement after the current routine returns."""
        depth = self.pointer.depth if self.pointer else 1
        return self._drive(lambda pointer: pointer.depth < depth, stepping=True)

    def pause(self) -> None:
        """Ask a running program to stop at the next statement or motion cycle (call from an action or a callback)."""
        self._pause = True

    def _drive(self, stop_here: Callable[[ProgramPointer], bool], stepping: bool = False) -> str:
        if self.finished:
            return self.status
        m = self.machine
        m.trace = stepping or self.tracing or bool(self.breakpoints)
        if self._gen is None:  # a first step stops before the first statement: the pointer shows it
            self._gen = self._program()
        self._pause = False
        self.status = "running"
        limit = sys.getrecursionlimit()
        sys.setrecursionlimit(max(limit, 20000))
        try:
            while True:
                event = next(self._gen)
                if event is TICK:
                    if self._pause:
                        self.status = "paused"
                        return self.status
                    continue
                self.pointer = self._pointer(event)  # type: ignore[arg-type]
                if self._pause or self.pointer.line in self.breakpoints or (stepping and stop_here(self.pointer)):
                    self.status = "paused"
                    return self.status
        except StopIteration:
            self.status = "finished"
        except (StopSignal, ReturnSignal):
            self._gen = iter(())
            self.status = "stopped"
        except RunError as error:
            self._fail(error)
        except Exception as error:  # a bug of ours: still no traceback for the user
            self._fail(RunError(f"internal error (a bug in orc_rpl, please report it): {type(error).__name__}: {error}"))
        finally:
            sys.setrecursionlimit(limit)
            m.trace = False
        return self.status

    def _pointer(self, statement: n.Statement) -> ProgramPointer:
        stack = self.machine.stack_entries()
        return ProgramPointer(statement, statement.span.line, statement.span.column, stack[-1].routine, stack)

    def _fail(self, error: RunError) -> None:
        """A run-time error: stop the robot on its path, keep the error with its place and call stack."""
        self.error = error
        self.status = "failed"
        self._gen = iter(())
        failed_at = self.statements.get(error.span.line) if error.span is not None else None
        if failed_at is not None:  # the pointer shows the failing statement: the pendant may restart there
            self.pointer = ProgramPointer(failed_at, failed_at.span.line, failed_at.span.column,
                                          error.stack[-1].routine if error.stack else "main", error.stack)
        robot = self.machine.robot
        try:
            robot.stop()
            end = robot.time_s() + STOP_TIMEOUT_S
            while robot.pending() > 0 and robot.time_s() < end:
                robot.tick()
        except Exception:  # the robot could not stop cleanly: the error we report is still the first one
            pass

    def report(self) -> str:
        """The failure as the user reads it: `file:line:col: message`, the line and caret, the call stack."""
        return self.error.report(self.path, self.source) if self.error else ""

    # -- one statement in context ---------------------------------------------------------

    def execute(self, text: str | n.Statement, line: int | None = None) -> str:
        """Run one statement typed at the pendant in the lexical context of the program pointer (or of `line`):
        its routine's scope and local variables, its FRAME block. Returns "ok" or the error's report."""
        try:
            stmt = parse_statement(text, "<pendant>") if isinstance(text, str) else text
        except SourceError as error:
            return error.format()
        routine, frame = self.context_of(line)
        try:
            for _ in self.statement_steps(stmt, routine, frame):
                pass
        except RunError as error:
            return error.report("<pendant>", text if isinstance(text, str) else None)
        return "ok"

    def statement_steps(self, stmt: n.Statement, routine: str | None = None, frame: str = "world",
                        settle: bool = True) -> Iterator[object]:
        """One statement in a lexical context (a routine's scope and its active locals, a FRAME block), as a
        generator yielding TICK per motion cycle, ending when the robot has arrived (unless `settle` is False:
        a declaration run while a jog moves leaves the jog alone); errors raise RunError."""
        scope = self.scopes.scope_of(routine).with_frame(frame)
        m = self.machine
        activation = next((a for a in reversed(m.stack) if a.routine == (routine or "main")), None)
        local_values = activation.locals if activation is not None else ({} if routine else m.globals)
        block = make_block(m, [self.compiler.statement(stmt, scope)])
        saved, m.trace = m.trace, False
        try:
            for event in block.gen(local_values):
                if event is TICK:
                    yield event
            if settle:
                yield from m.sync()
        except (StopSignal, ReturnSignal):
            return
        finally:
            m.trace = saved

    def context_of(self, line: int | None = None) -> tuple[str | None, str]:
        """(routine or None, FRAME) of the statement at `line` (default: the program pointer's)."""
        if line is None:
            line = self.pointer.line if self.pointer is not None else 0
        return self.contexts.get(line, (None, "world"))

    def restart_at(self, body: n.Body) -> str:
        """Set the program pointer: `body` (statements of the program, their nodes and lines kept) becomes what
        runs next, at the top level; variables keep their values. Returns the status after stopping before its
        first statement ("paused"), or "finished" when it is empty."""
        self.main = self.compiler.block(body, Scope())
        self._gen = None
        self.status, self.error, self.pointer = "ready", None, None
        return self.step_into()

    # -- results ----------------------------------------------------------------------------

    @property
    def prints(self) -> list[str]:
        return self.machine.prints

    @property
    def motions(self) -> int:
        return self.machine.motions

    def value(self, name: str) -> Any:
        """A global variable's value (for the pendant's watch view and tests)."""
        return self.machine.globals.get(name)


def run_program(program: n.Program, robot: RobotInterface, **options: Any) -> Executive:
    """Run a whole program to its end; the Executive keeps status, prints and error."""
    executive = Executive(program, robot, **options)
    executive.run()
    return executive
