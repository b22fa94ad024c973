"""How control leaves a statement: RPL exceptions, RETURN, STOP, and run-time errors with their place and call stack."""

from __future__ import annotations

from dataclasses import dataclass

from orc_rpl.errors import Diagnostic, Location, OrcError
from orc_rpl.syntax.nodes import Span


@dataclass(frozen=True, slots=True)
class StackEntry:
    """One call on the stack: the routine and where it was called from (the main program has no call site)."""

    routine: str                #: "main" for the program itself
    line: int                   #: of the call statement (0 for main)
    column: int

    def describe(self, path: str) -> str:
        return f"{path}:{self.line}:{self.column}: in {self.routine}" if self.line else f"{path}: in {self.routine}"


class ControlSignal(Exception):
    """Base of the exceptions that carry RPL control flow; never a bug and never shown with a traceback."""


class ReturnSignal(ControlSignal):
    """`RETURN [value]` leaving a routine."""

    def __init__(self, value: object = None) -> None:
        self.value = value


class StopSignal(ControlSignal):
    """`STOP`: the program ends; the robot stops on its path."""

    def __init__(self, span: Span) -> None:
        self.span = span


class RunError(ControlSignal):
    """A run-time error at a statement, or an RPL exception (`name` set) that a TRY may catch."""

    def __init__(self, message: str, span: Span | None = None, name: str | None = None,
                 stack: tuple[StackEntry, ...] = ()) -> None:
        super().__init__(message)
        self.message = message
        self.span = span
        self.name = name               #: the RPL exception name (NotFound, Unreachable, user names); None: not catchable
        self.stack = stack             #: the call stack when it happened, outermost first

    def located(self, span: Span, stack: tuple[StackEntry, ...]) -> RunError:
        """This error placed at a statement, if it has no place yet."""
        if self.span is None:
            self.span, self.stack = span, stack
        return self

    def diagnostic(self, path: str, source: str | None = None) -> Diagnostic:
        span = self.span or Span(1, 1, 1, 1)
        end_column = span.end_column if span.end_line == span.line else 0
        text = None
        if source is not None:
            lines = source.splitlines()
            text = lines[span.line - 1] if 1 <= span.line <= len(lines) else None
        return Diagnostic(Location(path, span.line, span.column, span.line, end_column), self.message, source_line=text)

    def report(self, path: str, source: str | None = None) -> str:
        """`file:line:col: message`, the line and caret, then the call stack innermost last."""
        text = self.diagnostic(path, source).format()
        calls = ["  " + entry.describe(path) for entry in self.stack if entry.line]
        if len(calls) > SHOWN_CALLS:
            # Endless recursion: the outermost calls say how it started, the innermost where it is.
            hidden = len(calls) - SHOWN_CALLS
            calls = calls[:3] + [f"  ... {hidden} more calls ..."] + calls[-(SHOWN_CALLS - 3):]
        if calls:
            text += "\ncall stack (innermost last):\n" + "\n".join(calls)
        return text


#: A printed call stack shows at most this many calls.
SHOWN_CALLS = 12


def rpl_exception(name: str, message: str | None = None) -> RunError:
    """An RPL exception that `ON name :` catches."""
    return RunError(message or f"exception {name} was raised and not caught", name=name)


class ProgramError(OrcError):
    """A program that cannot run at all (a broken tree the checker should have refused)."""
