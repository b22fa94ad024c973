"""The pendant's editor: the program tree and text, cursor and selection, structured edits, undo, journal and saving."""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

from orc_rpl.atomic import write_text_atomic
from orc_rpl.checking.checker import check_program
from orc_rpl.errors import Diagnostic, OrcError, SourceError
from orc_rpl.pendant import tree
from orc_rpl.pendant.events import EventLog
from orc_rpl.pendant.journal import Journal, JournalError, journal_path, recoverable
from orc_rpl.pendant.tree import BodyPath, EditError, Stop, reparse, stops
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.layout import ONLINE, keep_layout
from orc_rpl.syntax.lexicon import PREDEFINED_NAMES, is_reserved
from orc_rpl.syntax.parser import parse, parse_statement
from orc_rpl.syntax.printer import simple_statement
from orc_rpl.world.pose import Pose, readable_angles

_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")

#: How many edits :undo can take back.
UNDO_DEPTH = 200


class PendantError(OrcError):
    """A pendant command that cannot be carried out; the message says why and what to do."""


def number_text(value: float, unit: str, digits: int) -> str:
    """A literal as a person writes it: `812.35mm`, `-90deg`, `0`."""
    rounded = round(value, digits)
    if rounded == 0:
        return "0"
    text = f"{rounded:.{digits}f}".rstrip("0").rstrip(".")
    return text + unit


def pose_text(pose: Pose) -> str:
    """`POSE(x mm, y mm, z mm, a deg, b deg, c deg)` to 1 µm and 0.001 deg (the numbers of a taught position)."""
    pose = readable_angles(pose)
    lengths = [number_text(v * 1000.0, "mm", 3) for v in (pose.x, pose.y, pose.z)]
    # -180 deg and 180 deg are one angle: write the positive one, as a person would
    angles = [number_text(180.0 if abs(math.degrees(v) + 180.0) < 5e-4 else math.degrees(v), "deg", 3)
              for v in (pose.a, pose.b, pose.c)]
    return f"POSE({', '.join(lengths + angles)})"


def joints_text(q_rad: tuple[float, ...]) -> str:
    return "JOINTS(" + ", ".join(number_text(math.degrees(q), "deg", 3) for q in q_rad) + ")"


def context_of(stop: Stop) -> tuple[str | None, str]:
    """(routine, frame) a statement inserted at this stop gets: on a block's first line, the block's inside."""
    stmt = stop.statement
    if not stop.end and isinstance(stmt, n.FrameBlock):
        return stop.routine, stmt.frame.id
    if not stop.end and isinstance(stmt, n.Routine):
        return stmt.name.id, "world"
    return stop.routine, stop.frame


def _shift_path(path: BodyPath, index: int, at: int) -> tuple[BodyPath, int]:
    """Where a statement is after one statement was inserted at top-level index `at`."""
    if path:
        (first, key), rest = path[0], path[1:]
        return (((first + 1 if first >= at else first), key),) + rest, index
    return path, index + 1 if index >= at else index


class Editor:
    """The program being edited, owned here: every change goes through the tree, is journaled and can be undone.

    It knows nothing about the robot: teaching hands it the text of the position to declare.
    """

    def __init__(self, path: Path, text: str, saved_text: str | None, journal: Journal | None, registry: Any,
                 events: EventLog) -> None:
        self.path = path
        self.registry = registry
        self.events = events
        self.saved_text = saved_text            #: the file as last read or saved (None: no file yet)
        self.journal = journal
        try:
            self.program = parse(text, str(path))
        except SourceError as error:
            raise PendantError(f"cannot open {path}: it has syntax errors\n{error.format()}") from None
        self.text = text
        self.stops: list[Stop] = stops(self.program)
        self.cursor = 0
        self.mark: int | None = None
        self.originals: dict[str, str] = {}     #: position name -> its declaration before the first :modpos
        self._undo: list[str] = []
        self.on_change: list[Callable[[], None]] = []  #: called after every edit (the executive recompiles)
        self.moving_frames: dict[str, str] | None = None  #: the cell's moving frames the program may name (None: none)

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

    def context(self) -> tuple[str | None, str]:
        """(routine, frame) of the cursor: where a typed statement runs and a taught position is relative to."""
        return context_of(self.at_cursor) if self.stops else (None, "world")

    def commit(self, program: n.Program, action: str, cursor: tuple | None = None, cursor_line: int | None = None,
               text: str | None = None) -> None:
        """Make an edited tree the program: printed in the program's layout (statements the edit did not touch keep
        their text; the rest canonical), parsed back, journaled, undoable."""
        parsed: n.Program | None = None
        if text is None:  # (undo gives the text as it was)
            text, parsed = keep_layout(program, self.text, self.program, ONLINE, str(self.path))
        if parsed is None:
            try:
                parsed = parse(text, str(self.path))
            except SourceError:  # the printer and parser disagree: the canonical text says why, or refuses the edit
                text, parsed = reparse(program, str(self.path))
        if text == self.text:
            return
        self._undo.append(self.text)
        del self._undo[:-UNDO_DEPTH]
        self.text, self.program = text, parsed
        self.stops = stops(parsed)
        self.mark = None  # a selection is of statements that may have moved: it ends with the edit
        unjournaled: JournalError | None = None
        if self.journal is not None:
            try:
                self.journal.append(action, text)
            except JournalError as error:  # the edit stands; the user must hear that it is not safe yet
                unjournaled = error
        for listener in self.on_change:
            listener()
        if cursor is not None:
            self.locate(*cursor)
        else:
            self.goto(cursor_line if cursor_line is not None else 1, quiet=True)
        if unjournaled is not None:
            raise unjournaled

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
        if quiet:
            return ""
        if self.cursor_line != line:  # a blank or comment line, or past the end: say where the cursor went
            return f"line {line} holds no statement; cursor at line {self.cursor_line}"
        return f"cursor at line {self.cursor_line}"

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

    # -- names and positions --------------------------------------------------------------

    def declared(self) -> dict[str, n.Statement]:
        """Every name the program declares (positions, frames, tools, variables, routines, equipment)."""
        out: dict[str, n.Statement] = {}
        for node in self.program.walk():
            if isinstance(node, (n.Declaration, n.Install, n.Routine)):
                out.setdefault(node.name.id, node)
            elif isinstance(node, n.EnumDecl):
                out.setdefault(node.name.id, node)
                for member in node.members:
                    out.setdefault(member.id, node)
        return out

    def new_name(self, name: str) -> str:
        """`name` if a new position may take it; an EditError saying why not otherwise."""
        if not _NAME.fullmatch(name):
            raise EditError(f"'{name}' is not a name: use letters, digits and _ (pos1b, above_bin)")
        if is_reserved(name) or name in PREDEFINED_NAMES:
            raise EditError(f"'{name}' is a reserved or predefined word and cannot name a position")
        existing = self.declared().get(name)
        if existing is not None:
            hint = f" (:modpos {name} touches it up)" if isinstance(existing, n.Declaration) and existing.kind == "POS" else ""
            raise EditError(f"'{name}' is already declared at line {existing.span.line}{hint}")
        return name

    def free_name(self) -> str:
        names = self.declared()
        return next(f"p{i}" for i in range(1, 10000) if f"p{i}" not in names)

    def position(self, name: str) -> tuple[n.Declaration, Stop]:
        """The declaration of position `name` and where it stands."""
        for stop in self.stops:
            stmt = stop.statement
            if not stop.end and isinstance(stmt, n.Declaration) and stmt.kind == "POS" and stmt.name.id == name:
                return stmt, stop
        raise EditError(f"no position '{name}' is declared (:teach {name} declares it)")

    def _declaration_index(self, frame: str) -> int:
        """Where a taught position's declaration goes: after the declarations at the top of the program (and after
        its frame's declaration), so it has its value before any statement uses it."""
        body = self.program.body
        index = 0
        for i, stmt in enumerate(body):
            if isinstance(stmt, (n.Declaration, n.EnumDecl, n.Install)):
                index = i + 1
            elif not isinstance(stmt, (n.Comment, n.Blank)):
                break
        for i, stmt in enumerate(body):
            if isinstance(stmt, n.Declaration) and stmt.kind == "FRAME" and stmt.name.id == frame and i >= index:
                index = i + 1
        return index

    # -- teaching: the robot's pose arrives as text ------------------------------------------

    def declare_position(self, name: str, value_text: str, frame: str, action: str) -> n.Statement:
        """Declare `POS name = value_text` where positions relative to `frame` belong; the cursor stays put."""
        declaration = parse_statement(f"POS {name} = {value_text}", "<teach>")
        at = self._declaration_index(frame)
        program = tree.replace_body(self.program, (), self.program.body[:at] + (declaration,) + self.program.body[at:])
        keep = _shift_path(self.at_cursor.body, self.at_cursor.index, at) if self.stops else ((), 0)
        self.commit(program, action, cursor=(*keep, self.at_cursor.end if self.stops else False))
        return declaration

    def insert_move(self, name: str, value_text: str, frame: str, tool: str) -> n.Statement:
        """Declare `POS name = value_text` and insert `MOVE tool TO name` after the cursor's statement, in its block."""
        declaration = parse_statement(f"POS {name} = {value_text}", "<teach>")
        motion = parse_statement(f"MOVE {tool} TO {name}", "<insert>")
        if not self.stops:
            self.commit(n.Program((declaration, motion)), f"insert move {name}", cursor=((), 1, False))
            return declaration
        program, path, index = tree.insert_at(self.program, self.at_cursor, (motion,))
        at = self._declaration_index(frame)
        program = tree.replace_body(program, (), program.body[:at] + (declaration,) + program.body[at:])
        path, index = _shift_path(path, index, at)
        self.commit(program, f"insert move {name}", cursor=(path, index, False))
        return declaration

    def touch_up(self, name: str, value_text: str) -> n.Statement:
        """`POS name = value_text` replaces the position's declaration (its comment kept, its original remembered)."""
        declaration, stop = self.position(name)
        new = parse_statement(f"POS {name} = {value_text}", "<modpos>")
        new = type(new)(new.kind, new.name, new.value, new.frame, declaration.comment)  # keep the line's comment
        self.originals.setdefault(name, simple_statement(declaration))
        keep = (self.at_cursor.body, self.at_cursor.index, self.at_cursor.end)
        self.commit(tree.replace_at(self.program, stop.body, stop.index, new), f"modpos {name}", cursor=keep)
        return new

    # -- statements -------------------------------------------------------------------------

    def insert(self, text: str) -> str:
        """Insert a statement (or a whole block) after the cursor's statement."""
        statement = _parse_one(text)
        if not self.stops:
            self.commit(n.Program((statement,)), "insert", cursor=((), 0, False))
        else:
            program, path, index = tree.insert_at(self.program, self.at_cursor, (statement,))
            self.commit(program, "insert", cursor=(path, index, False))
        return self.events.record(f"inserted at line {self.cursor_line}: {text.splitlines()[0].strip()}")

    def replace(self, text: str) -> str:
        """Edit in place: the cursor's statement becomes `text` (which must parse)."""
        path, first, last = self.selection()
        statement = _parse_one(text)
        self.commit(tree.replace_at(self.program, path, first, statement), "replace", cursor=(path, first, False))
        return self.events.record(f"line {self.cursor_line} is now: {text.splitlines()[0].strip()}")

    def delete(self) -> str:
        path, first, last = self.selection()
        program = tree.delete_range(self.program, path, first, last)
        left = len(tree.body_at(program, path))
        self.mark = None
        if left:
            cursor = (path, min(first, left - 1), False)
        elif path:
            cursor = (path[:-1], path[-1][0], False)
        else:
            cursor = ((), 0, False)
        self.commit(program, "delete", cursor=cursor)
        count = last - first + 1
        return self.events.record(f"deleted {count} statement{'s' if count != 1 else ''}")

    def wrap(self, frame: str) -> str:
        """Wrap the selection in `FRAME frame ... ENDFRAME` (the frame must be declared)."""
        known = self.declared().get(frame)
        if not (isinstance(known, n.Declaration) and known.kind == "FRAME"):
            raise EditError(f"'{frame}' is not a declared FRAME; declare it first: FRAME {frame} = POSE(...)")
        path, first, last = self.selection()
        self.mark = None
        self.commit(tree.wrap_frame(self.program, path, first, last, frame), f"wrap FRAME {frame}", cursor=(path, first, False))
        problems = self.check_diagnostics()
        note = f"; {len(problems)} check error(s): :check shows them" if problems else ""
        return self.events.record(f"wrapped {last - first + 1} statement(s) in FRAME {frame}{note}")

    def shift(self, direction: str) -> str:
        offset = {"up": -1, "down": 1}.get(direction)
        if offset is None:
            raise EditError(f":shift: expected up or down, got {direction!r}")
        path, first, last = self.selection()
        self.commit(tree.shift(self.program, path, first, last, offset), f"shift {direction}",
                    cursor=(path, (self.at_cursor.index if self.mark is None else first) + offset, False))
        if self.mark is not None:
            self.mark = None
        return self.events.record(f"moved {last - first + 1} statement(s) {direction}")

    def undo(self, name: str | None = None) -> str:
        """Take back the last edit; `:undo NAME` restores a touched-up position's original numbers."""
        if name is not None:
            original = self.originals.get(name)
            if original is None:
                raise EditError(f"position '{name}' was not touched up in this session (:positions lists them)")
            _, stop = self.position(name)
            self.commit(tree.replace_at(self.program, stop.body, stop.index, parse_statement(original)),
                        f"undo modpos {name}", cursor=(self.at_cursor.body, self.at_cursor.index, self.at_cursor.end))
            del self.originals[name]
            return self.events.record(f"restored {original}")
        if not self._undo:
            raise EditError("nothing to undo")
        line = self.cursor_line
        previous = self._undo.pop()
        self.commit(parse(previous, str(self.path)), "undo", cursor_line=line, text=previous)
        self._undo.pop()  # commit pushed the undone text: undoing is not itself undoable
        return self.events.record("undid the last edit")

    def check_diagnostics(self) -> list[Diagnostic]:
        """The checker's findings on the program as it is now."""
        return check_program(self.program, str(self.path), self.registry, None, self.moving_frames)

    # -- saving and recovery --------------------------------------------------------------

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
        return self.events.record(f"saved {target} ({len(self.text.splitlines())} lines)")

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
        return self.events.record(f"recovered {len(entries)} unsaved edits from {journal_path(self.path).name}")

    def discard_recovery(self) -> str:
        if self.journal is not None:
            self.journal.clear()
        return self.events.record("discarded the unsaved edits of the previous session")

    def close(self) -> None:
        if self.journal is not None:
            self.journal.close()


def _parse_one(text: str) -> n.Statement:
    try:
        return parse_statement(text, "<pendant>")
    except SourceError as error:
        raise EditError(error.format()) from None
