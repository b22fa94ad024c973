"""Teaching, touch-up and structured edits of the session's program, all through the syntax tree."""

from __future__ import annotations

import math
import re
from typing import TYPE_CHECKING

import numpy as np

from orc_rpl.errors import SourceError
from orc_rpl.executive.signals import RunError
from orc_rpl.pendant import tree
from orc_rpl.pendant.tree import BodyPath, EditError, Stop
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.lexicon import PREDEFINED_NAMES, is_reserved
from orc_rpl.syntax.parser import parse, parse_statement
from orc_rpl.syntax.printer import simple_statement
from orc_rpl.world.pose import Joints, Pose, readable_angles

if TYPE_CHECKING:
    from orc_rpl.pendant.session import PendantSession

_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


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


class EditingMixin:
    """:teach, :insert, :modpos, :delete, :replace, :wrap, :shift and :undo."""

    # -- names and positions --------------------------------------------------------------

    def declared(self: PendantSession) -> dict[str, n.Statement]:
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

    def _new_name(self: PendantSession, name: str) -> str:
        if not _NAME.fullmatch(name):
            raise EditError(f"'{name}' is not a name: use letters, digits and _ (pos1b, above_bin)")
        if is_reserved(name) or name in PREDEFINED_NAMES:
            raise EditError(f"'{name}' is a reserved or predefined word and cannot name a position")
        existing = self.declared().get(name)
        if existing is not None:
            hint = f" (:modpos {name} touches it up)" if isinstance(existing, n.Declaration) and existing.kind == "POS" else ""
            raise EditError(f"'{name}' is already declared at line {existing.span.line}{hint}")
        return name

    def _free_name(self: PendantSession) -> str:
        names = self.declared()
        return next(f"p{i}" for i in range(1, 10000) if f"p{i}" not in names)

    def _current_pose_text(self: PendantSession, frame: str) -> str:
        """The TCP of the pendant's tool, relative to `frame`, as RPL text (after the robot came to rest)."""
        self.robot.run_until_idle()
        ex = self.executive()
        try:
            frame_world = ex.machine.frame_matrix(frame)
        except RunError as error:
            raise EditError(f"cannot teach relative to FRAME {frame}: {error.message}") from None
        world = self.robot.commanded_tcp(self.tool_pose())
        relative = Pose.from_matrix(np.linalg.inv(frame_world) @ world.matrix(), frame)
        return pose_text(relative) + (f" IN {frame}" if frame != "world" else "")

    def _declaration_index(self: PendantSession, frame: str) -> int:
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

    # -- teaching ---------------------------------------------------------------------------

    def teach(self: PendantSession, name: str, action: str | None = None) -> str:
        """Declare a position at the current pose, relative to the FRAME block containing the cursor."""
        name = self._new_name(name)
        _, frame = context_of(self.at_cursor) if self.stops else (None, "world")
        declaration = parse_statement(f"POS {name} = {self._current_pose_text(frame)}", "<teach>")
        at = self._declaration_index(frame)
        program = tree.replace_body(self.program, (), self.program.body[:at] + (declaration,) + self.program.body[at:])
        keep = _shift_path(self.at_cursor.body, self.at_cursor.index, at) if self.stops else ((), 0)
        self.commit(program, action or f"teach {name}", cursor=(*keep, self.at_cursor.end if self.stops else False))
        where = f"relative to FRAME {frame}" if frame != "world" else "relative to world (the cursor is outside every FRAME block)"
        return self.event(f"taught {simple_statement(declaration)}  -- {where}")

    def insert_move(self: PendantSession, name: str | None = None) -> str:
        """Teach a position and insert `MOVE <tool> TO <it>` after the cursor's statement, inside the right block."""
        name = self._new_name(name) if name else self._free_name()
        _, frame = context_of(self.at_cursor) if self.stops else (None, "world")
        declaration = parse_statement(f"POS {name} = {self._current_pose_text(frame)}", "<teach>")
        motion = parse_statement(f"MOVE {self.tool} TO {name}", "<insert>")
        if not self.stops:
            self.commit(n.Program((declaration, motion)), f"insert move {name}", cursor=((), 1, False))
            return self.event(f"inserted MOVE {self.tool} TO {name} at line {self.cursor_line}")
        program, path, index = tree.insert_at(self.program, self.at_cursor, (motion,))
        at = self._declaration_index(frame)
        program = tree.replace_body(program, (), program.body[:at] + (declaration,) + program.body[at:])
        path, index = _shift_path(path, index, at)
        self.commit(program, f"insert move {name}", cursor=(path, index, False))
        self.event(f"taught {simple_statement(declaration)}")
        return self.event(f"inserted MOVE {self.tool} TO {name} at line {self.cursor_line}"
                          + (f", inside FRAME {frame}" if frame != "world" else ""))

    def modpos(self: PendantSession, name: str) -> str:
        """Touch up a position: its numbers become the current pose, in the frame it is declared relative to."""
        declaration, stop = self._position(name)
        frame = declaration.frame.id if declaration.frame is not None else "world"
        value = self.executive().machine.globals.get(name)
        if type(value) is Joints or (isinstance(declaration.value, n.Call) and getattr(declaration.value.function, "id", "") == "JOINTS"):
            self.robot.run_until_idle()
            text = f"POS {name} = {joints_text(tuple(self.robot.layer.reference_q()))}"
        else:
            text = f"POS {name} = {self._current_pose_text(frame)}"
        new = parse_statement(text, "<modpos>")
        new = type(new)(new.kind, new.name, new.value, new.frame, declaration.comment)  # keep the line's comment
        self.originals.setdefault(name, simple_statement(declaration))
        keep = (self.at_cursor.body, self.at_cursor.index, self.at_cursor.end)
        self.commit(tree.replace_at(self.program, stop.body, stop.index, new), f"modpos {name}", cursor=keep)
        return self.event(f"modpos {simple_statement(new)}  (original kept: {self.originals[name]})")

    def _position(self: PendantSession, name: str) -> tuple[n.Declaration, Stop]:
        for stop in self.stops:
            stmt = stop.statement
            if not stop.end and isinstance(stmt, n.Declaration) and stmt.kind == "POS" and stmt.name.id == name:
                return stmt, stop
        raise EditError(f"no position '{name}' is declared (:teach {name} declares it)")

    # -- statements -------------------------------------------------------------------------

    def insert(self: PendantSession, text: str) -> str:
        """Insert a statement (or a whole block) after the cursor's statement."""
        statement = _parse_one(text)
        if not self.stops:
            self.commit(n.Program((statement,)), "insert", cursor=((), 0, False))
        else:
            program, path, index = tree.insert_at(self.program, self.at_cursor, (statement,))
            self.commit(program, "insert", cursor=(path, index, False))
        return self.event(f"inserted at line {self.cursor_line}: {text.splitlines()[0].strip()}")

    def replace(self: PendantSession, text: str) -> str:
        """Edit in place: the cursor's statement becomes `text` (which must parse)."""
        path, first, last = self.selection()
        statement = _parse_one(text)
        self.commit(tree.replace_at(self.program, path, first, statement), "replace", cursor=(path, first, False))
        return self.event(f"line {self.cursor_line} is now: {text.splitlines()[0].strip()}")

    def delete(self: PendantSession) -> str:
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
        return self.event(f"deleted {count} statement{'s' if count != 1 else ''}")

    def wrap(self: PendantSession, frame: str) -> str:
        """Wrap the selection in `FRAME frame ... ENDFRAME` (the frame must be declared)."""
        known = self.declared().get(frame)
        if not (isinstance(known, n.Declaration) and known.kind == "FRAME"):
            raise EditError(f"'{frame}' is not a declared FRAME; declare it first: FRAME {frame} = POSE(...)")
        path, first, last = self.selection()
        self.mark = None
        self.commit(tree.wrap_frame(self.program, path, first, last, frame), f"wrap FRAME {frame}", cursor=(path, first, False))
        problems = self.check_diagnostics()
        note = f"; {len(problems)} check error(s): :check shows them" if problems else ""
        return self.event(f"wrapped {last - first + 1} statement(s) in FRAME {frame}{note}")

    def shift(self: PendantSession, direction: str) -> str:
        offset = {"up": -1, "down": 1}.get(direction)
        if offset is None:
            raise EditError(f":shift: expected up or down, got {direction!r}")
        path, first, last = self.selection()
        self.commit(tree.shift(self.program, path, first, last, offset), f"shift {direction}",
                    cursor=(path, (self.at_cursor.index if self.mark is None else first) + offset, False))
        if self.mark is not None:
            self.mark = None
        return self.event(f"moved {last - first + 1} statement(s) {direction}")

    def undo(self: PendantSession, name: str | None = None) -> str:
        """Take back the last edit; `:undo NAME` restores a touched-up position's original numbers."""
        if name is not None:
            original = self.originals.get(name)
            if original is None:
                raise EditError(f"position '{name}' was not touched up in this session (:positions lists them)")
            _, stop = self._position(name)
            self.commit(tree.replace_at(self.program, stop.body, stop.index, parse_statement(original)),
                        f"undo modpos {name}", cursor=(self.at_cursor.body, self.at_cursor.index, self.at_cursor.end))
            del self.originals[name]
            return self.event(f"restored {original}")
        if not self._undo:
            raise EditError("nothing to undo")
        line = self.cursor_line
        previous = self._undo.pop()
        self.commit(parse(previous, str(self.path)), "undo", cursor_line=line)
        self._undo.pop()  # commit pushed the undone text: undoing is not itself undoable
        return self.event("undid the last edit")


def _parse_one(text: str) -> n.Statement:
    try:
        return parse_statement(text, "<pendant>")
    except SourceError as error:
        raise EditError(error.format()) from None
