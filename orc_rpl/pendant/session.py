"""The pendant's headless session: program tree, cursor, positions, journal, robot and executive; every `:command` is a method."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from orc_rpl.application.standard_behaviour import runtime_registry
from orc_rpl.atomic import write_text_atomic
from orc_rpl.errors import OrcError, SourceError
from orc_rpl.pendant.editing import EditingMixin
from orc_rpl.pendant.execution import ExecutionMixin
from orc_rpl.pendant.journal import Journal, journal_path, recoverable
from orc_rpl.pendant.panels import PanelsMixin
from orc_rpl.pendant.robot import PendantRobot
from orc_rpl.pendant.tree import EditError, Stop, reparse, stops
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.parser import parse

#: How many edits :undo can take back.
UNDO_DEPTH = 200


class PendantError(OrcError):
    """A pendant command that cannot be carried out; the message says why and what to do."""


class PendantSession(EditingMixin, ExecutionMixin, PanelsMixin):
    """One pendant: every method is a command and returns the text to show; nothing here knows about the terminal.

    `synchronous=True` (tests, scripts) runs each motion to its end in simulated time before returning;
    the terminal application passes False and advances time with `pump()`. The session starts in manual mode
    (every motion capped at 250 mm/s at the TCP), as an industrial pendant does.
    """

    def __init__(self, path: str | Path | None = None, text: str | None = None, robot: PendantRobot | None = None,
                 registry: object = None, journal: bool = True, synchronous: bool = True,
                 on_print: Callable[[str], None] | None = None, mode: str = "manual") -> None:
        self.path = Path(path) if path is not None else Path("untitled.rpl")
        self.registry = registry or runtime_registry()
        self.robot = robot or PendantRobot.virtual()
        self.synchronous = synchronous
        self.on_print = on_print
        self.log: list[str] = []
        self.printed: list[str] = []
        self.originals: dict[str, str] = {}     #: position name -> its declaration before the first :modpos
        self._undo: list[str] = []
        self.journal = Journal(journal_path(self.path)) if journal else None
        if text is None:
            text = self.path.read_text(encoding="utf-8") if self.path.exists() else ""
        self.saved_text = self.path.read_text(encoding="utf-8") if self.path.exists() else None
        try:
            self.program = parse(text, str(self.path))
        except SourceError as error:
            raise PendantError(f"cannot open {self.path}: it has syntax errors\n{error.format()}") from None
        self.text = text
        self.stops: list[Stop] = stops(self.program)
        self.cursor = 0
        self.mark: int | None = None
        self._init_execution(mode)  # manual by default, as an industrial pendant starts in T1
        self.event(f"opened {self.path} ({len(text.splitlines())} lines)")

    # -- recovery ----------------------------------------------------------------------

    @classmethod
    def open(cls, path: str | Path, recover: bool = False, **options: object) -> PendantSession:
        """Open a program file; with `recover`, take the program from the autosave journal of a killed session."""
        session = cls(path, **options)  # type: ignore[arg-type]
        if recover:
            session.recover()
        return session

    def pending_recovery(self) -> str | None:
        """A one-line description of unsaved edits left in the journal by a killed session, or None."""
        entries = recoverable(self.path, self.saved_text)
        if not entries:
            return None
        actions = ", ".join(e.action for e in entries[-3:])
        return f"{len(entries)} unsaved edit{'s' if len(entries) != 1 else ''} (last: {actions})"

    def recover(self) -> str:
        """Take the program from the journal (every taught position and edit of the killed session)."""
        entries = recoverable(self.path, self.saved_text)
        if not entries:
            return "nothing to recover"
        # commit appends to the same journal, so a second kill before :save still loses nothing
        self.commit(parse(entries[-1].text, str(self.path)), f"recovered {len(entries)} edits", cursor_line=1)
        return self.event(f"recovered {len(entries)} unsaved edits from {journal_path(self.path).name}")

    def discard_recovery(self) -> str:
        if self.journal is not None:
            self.journal.clear()
        return self.event("discarded the unsaved edits of the previous session")

    # -- the program and the cursor ----------------------------------------------------

    @property
    def at_cursor(self) -> Stop:
        if not self.stops:
            raise EditError("the program is empty: :insert a statement, or :insert move")
        return self.stops[min(self.cursor, len(self.stops) - 1)]

    @property
    def cursor_line(self) -> int:
        return self.at_cursor.line if self.stops else 0

    @property
    def modified(self) -> bool:
        """Edits not yet saved (an empty new program is not an edit)."""
        return self.text != (self.saved_text if self.saved_text is not None else "")

    def commit(self, program: n.Program, action: str, cursor: tuple | None = None, cursor_line: int | None = None) -> None:
        """Make an edited tree the program: printed canonically, parsed back, journaled, undoable."""
        text, parsed = reparse(program, str(self.path))
        if text == self.text:
            return
        self._undo.append(self.text)
        del self._undo[:-UNDO_DEPTH]
        self.text, self.program = text, parsed
        self.stops = stops(parsed)
        self.mark = None  # a selection is of statements that may have moved: it ends with the edit
        if self.journal is not None:
            self.journal.append(action, text)
        self._program_changed()
        if cursor is not None:
            self.locate(*cursor)
        else:
            self.goto(cursor_line if cursor_line is not None else 1, quiet=True)

    def locate(self, body: tuple, index: int, end: bool = False) -> None:
        """The cursor to the statement at `index` of a body (after an edit, whose lines have moved)."""
        for i, stop in enumerate(self.stops):
            if stop.body == body and stop.index == index and stop.end == end:
                self.cursor = i
                return
        self.cursor = min(self.cursor, max(0, len(self.stops) - 1))

    def move_cursor(self, delta: int) -> str:
        if self.stops:
            self.cursor = max(0, min(len(self.stops) - 1, self.cursor + delta))
        return ""

    def goto(self, line: int, end: bool = False, quiet: bool = False) -> str:
        """The cursor to the statement at (or first after) a line."""
        if not self.stops:
            return ""
        candidates = [i for i, s in enumerate(self.stops) if s.line >= line]
        exact = [i for i in candidates if self.stops[i].line == line and self.stops[i].end == end]
        self.cursor = exact[0] if exact else candidates[0] if candidates else len(self.stops) - 1
        return "" if quiet else f"cursor at line {self.cursor_line}"

    def select(self) -> str:
        """Start (or clear) a selection at the cursor; the arrows extend it inside one block."""
        if self.mark is not None:
            self.mark = None
            return "selection cleared"
        self.mark = self.cursor
        return "selecting: move the cursor, then :delete, :wrap FRAME name, :shift up|down"

    def selection(self) -> tuple[tuple, int, int]:
        """The selected statements: their body and first/last index (the cursor's statement without a selection)."""
        here = self.at_cursor
        if self.mark is None:
            if here.end:
                raise EditError("the cursor is on an END line: move it to a statement")
            return here.body, here.index, here.index
        there = self.stops[self.mark]
        if there.body != here.body:
            raise EditError("a selection must stay inside one block")
        first, last = sorted((here.index, there.index))
        return here.body, first, last

    # -- saving --------------------------------------------------------------------------

    def save(self, file: str | None = None) -> str:
        """Write the program atomically (temporary file and rename); the journal then has nothing to recover."""
        target = Path(file) if file else self.path
        if target.suffix != ".rpl":
            raise PendantError(f":save {target}: a program file must end in .rpl")
        try:
            write_text_atomic(target, self.text)
        except OSError as error:
            raise PendantError(f":save {target}: {error.strerror or error}") from None
        if target.resolve() == self.path.resolve():
            self.saved_text = self.text
            if self.journal is not None:
                self.journal.clear()
        elif file:
            if self.journal is not None:
                self.journal.clear()
            self.path, self.saved_text = target, self.text
            self.journal = Journal(journal_path(target)) if self.journal is not None else None
        return self.event(f"saved {target} ({len(self.text.splitlines())} lines)")

    def close(self) -> None:
        if self.journal is not None:
            self.journal.close()

    # -- events ----------------------------------------------------------------------------

    def event(self, text: str) -> str:
        """Log an event (shown by :log) and return it as the command's answer."""
        self.log.append(f"{self.robot.time_s():9.3f}s  {text}")
        return text
