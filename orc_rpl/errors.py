"""The project's error types: every failure a user can cause is one of these, never a bare traceback."""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True, slots=True)
class Location:
    """Where something is in a source file: 1-based line and column, end exclusive."""

    path: str                 #: file name as the user gave it ("<input>" for typed text)
    line: int                 #: first line, 1-based
    column: int               #: first column, 1-based
    end_line: int = 0         #: last line (0: same as line)
    end_column: int = 0       #: column after the last character (0: one character)


class OrcError(Exception):
    """Base of every error orc_rpl reports to a user."""


@dataclass
class Diagnostic:
    """One message about a place in a file: `file:line:col: message`, the line, a caret, a hint."""

    location: Location
    message: str
    hint: str = ""
    severity: str = "error"
    source_line: str | None = field(default=None, repr=False)

    def format(self, source: str | None = None) -> str:
        """The message as the user reads it, with the source line and a caret when known."""
        loc = self.location
        head = f"{loc.path}:{loc.line}:{loc.column}: {self.message}"
        if self.severity == "note":
            return head
        line_text = self.source_line
        if line_text is None and source is not None:
            lines = source.splitlines()
            if 1 <= loc.line <= len(lines):
                line_text = lines[loc.line - 1]
        parts = [head]
        if line_text is not None:
            gutter = f"{loc.line:>5} | "
            parts.append(gutter + line_text)
            if loc.end_line in (0, loc.line) and loc.end_column > loc.column:
                width = loc.end_column - loc.column
            else:
                width = max(1, len(line_text.rstrip()) - loc.column + 1) if loc.end_line > loc.line else 1
            parts.append(" " * 6 + "| " + " " * (loc.column - 1) + "^" * max(1, width))
        if self.hint:
            parts.append(f"      = hint: {self.hint}")
        return "\n".join(parts)


#: Diagnostics printed per file; the rest are counted in one last line (16,000 stray ENDIFs print 50).
MAX_SHOWN = 50


def capped(diagnostics: list[Diagnostic]) -> list[Diagnostic]:
    """At most MAX_SHOWN diagnostics, then a note at the last one saying how many more were found."""
    if len(diagnostics) <= MAX_SHOWN:
        return diagnostics
    rest = len(diagnostics) - MAX_SHOWN
    last = diagnostics[MAX_SHOWN - 1]
    note = Diagnostic(last.location, f"{rest} more error{'s' if rest != 1 else ''} not shown (at most {MAX_SHOWN} per file)",
                      severity="note")
    return diagnostics[:MAX_SHOWN] + [note]


class SourceError(OrcError):
    """One or more diagnostics about a source file (syntax, check or world-model errors)."""

    def __init__(self, diagnostics: list[Diagnostic], source: str | None = None) -> None:
        self.diagnostics = diagnostics
        self.source = source
        super().__init__(self.format())

    def format(self) -> str:
        """All diagnostics, each with its line and caret, in file order."""
        return "\n".join(d.format(self.source) for d in capped(self.diagnostics))


class MotionFault(OrcError):
    """A fault the robot program can catch by name (`ON Unreachable :`)."""

    rpl_name = "MotionFault"


class Unreachable(MotionFault):
    """No joint configuration reaches the target (outside the workspace or the joint ranges)."""

    rpl_name = "Unreachable"


class JointLimit(MotionFault):
    """A commanded or planned joint position leaves the joint's range."""

    rpl_name = "JointLimit"


class NotFound(MotionFault):
    """An `UNTIL` condition never became true before the motion reached its target."""

    rpl_name = "NotFound"


class Timeout(MotionFault):
    """A wait ran out of time."""

    rpl_name = "Timeout"


class Collision(MotionFault):
    """The robot or its tool touched something in the cell that is not its work: a collision stop."""

    rpl_name = "Collision"


class SensorFault(MotionFault):
    """A sensor failed to deliver a value (lost link, bad reply)."""

    rpl_name = "SensorFault"


class DriveFault(MotionFault):
    """A drive failed: a servo stopped answering, or raised an alarm (overload, overheating); the message names it."""

    rpl_name = "DriveFault"


class PlanningError(OrcError):
    """The planner could not produce a trajectory within the limits (with the reason)."""


class UsageError(OrcError):
    """A command-line or API argument is wrong; the message names the argument."""


class InternalError(OrcError):
    """A bug of ours, not of the user: the message says so."""

    def __init__(self, message: str) -> None:
        super().__init__(f"internal error (a bug in orc_rpl, please report it): {message}")
