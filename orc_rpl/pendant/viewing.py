"""The pendant's 3D view part: keeps a browser view in step with jogging, teaching, stepping and running."""

from __future__ import annotations

from typing import Any, Protocol

import numpy as np

from orc_rpl.errors import OrcError
from orc_rpl.pendant.editing import Editor
from orc_rpl.pendant.events import EventLog
from orc_rpl.pendant.execution import Execution
from orc_rpl.pendant.robot import PendantRobot
from orc_rpl.syntax import nodes as n

#: Planned moves whose statement line the part remembers (the view keeps fewer paths on screen anyway).
MOVES_REMEMBERED = 200


class View(Protocol):
    """What the part needs of a view (the 3D view's LiveView is one; the pendant does not import it)."""

    def follow(self, executive: Any, program: n.Program) -> None: ...
    def on_tick(self) -> None: ...
    def update(self) -> None: ...
    def highlight(self, position: str | None = None, move_id: int | None = None) -> None: ...


class ViewLink:
    """Owns the link from the session to a view: the robot each motion cycle, the program after each edit, the
    position at the cursor and the motion at the program pointer highlighted. It reads the other parts; it commands
    nothing. Call `refresh()` after each command and while the screen idles (it costs nothing while the robot moves);
    `close()` at the end."""

    def __init__(self, view: View, editor: Editor, execution: Execution, robot: PendantRobot, events: EventLog,
                 url: str | None = None) -> None:
        self.view, self.editor, self.execution, self.robot, self.events = view, editor, execution, robot, events
        self.url = url
        self.lines: dict[int, int] = {}           #: planned move id -> line of the program statement that asked
        self._followed: tuple[Any, Any] = (None, None)
        self._shown: tuple[str | None, int | None] = (None, None)
        self._ticks = -1                          #: the robot's motion cycles when the view was last brought up to date
        robot.tick_listeners.add(view.on_tick)
        robot.layer.plan_listeners.add(self._planned)
        if url is not None:
            events.record(f"the 3D view is at {url}")

    def _planned(self, move_id: int, tcp_m: np.ndarray) -> None:
        """The motion layer's planned-path signal: a program motion's path is remembered with its statement's line."""
        if self.robot.asking_line:
            self.lines[move_id] = self.robot.asking_line
            while len(self.lines) > MOVES_REMEMBERED:
                del self.lines[next(iter(self.lines))]

    # -- what is selected --------------------------------------------------------------------

    def selected_position(self) -> str | None:
        """The position at the cursor: the one a POS, PATH or FRAME declaration declares, or a motion's target."""
        try:
            stop = self.editor.at_cursor
        except OrcError:  # an empty program
            return None
        stmt = stop.statement
        if isinstance(stmt, n.Declaration) and stmt.kind in ("POS", "PATH", "FRAME"):
            return stmt.name.id
        if isinstance(stmt, n.Motion) and isinstance(stmt.target, n.Name):
            return stmt.target.id
        return None

    def pointer_move(self) -> int | None:
        """The planned move of the statement at the program pointer (the latest one, when it ran before)."""
        pointer = self.execution.executive().pointer
        if pointer is None:
            return None
        moves = [move_id for move_id, line in self.lines.items() if line == pointer.line]
        return moves[-1] if moves else None

    # -- keeping in step ---------------------------------------------------------------------

    def refresh(self) -> None:
        """Show the program as it is now (after an edit the executive is new) and the selection, if either changed."""
        executive, program = self.execution.executive(), self.editor.program
        if executive is not self._followed[0] or program is not self._followed[1]:
            self._followed = (executive, program)
            self.view.follow(executive, program)
        chosen = (self.selected_position(), self.pointer_move())
        changed = chosen != self._shown
        if changed:
            self._shown = chosen
            self.view.highlight(*chosen)
        # while the robot moves, its motion cycles feed the view (on_tick); once it stands, its last cycles may have
        # fallen between two of the view's samples: show where it stopped, once
        standing = not self.execution.busy and self.robot.pending() == 0
        if changed or (standing and self._ticks != self.robot.ticks):
            self._ticks = self.robot.ticks
            self.view.update()

    def close(self) -> None:
        """Stop feeding the view (the view itself is closed by whoever opened it)."""
        self.robot.tick_listeners.discard(self.view.on_tick)
        self.robot.layer.plan_listeners.discard(self._planned)
