"""The pendant's program pointer: :pp with its approach motion, and :back over the last motion."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from orc_rpl.motion import CartesianMotion, JointMotion, MoveStatus, Params
from orc_rpl.pendant.adapter import point_at
from orc_rpl.pendant.editing import Editor
from orc_rpl.pendant.events import EventLog
from orc_rpl.pendant.execution import Execution
from orc_rpl.pendant.robot import PendantRobot
from orc_rpl.pendant.tree import EditError, Stop
from orc_rpl.syntax import nodes as n
from orc_rpl.world.pose import Pose

#: :pp's approach motion and :back run at this fraction of the robot's speed (times the override).
APPROACH_FRACTION = 0.1
#: :back along a straight line runs at this TCP speed (times the override).
BACK_TCP_SPEED_M_S = 0.1


class ProgramPointer:
    """The program pointer set anywhere, safely; the robot taken back over its motions."""

    def __init__(self, editor: Editor, execution: Execution, robot: PendantRobot, events: EventLog) -> None:
        self.editor = editor
        self.execution = execution
        self.robot = robot
        self.events = events

    def pp(self) -> str:
        """Program pointer to the cursor; then a slow joint motion to where the statement starts (the end of the
        motion before it), so that :run or :step go on exactly as the program would."""
        stop = self.editor.at_cursor
        ex = self.execution.executive()
        status = point_at(ex, self.editor.program, stop)
        if status != "paused":
            return self.events.record("program pointer at the end of the program")
        message = self.events.record(f"program pointer at line {ex.pointer.line}")
        approach = self._approach(stop)
        if approach is None:
            return message
        previous, frame = approach
        result = self.execution.statement_job("approach", previous, None, frame, 0, None, quiet=True)
        return f"{message}; approach to the end of line {previous.span.line}'s motion at " \
               f"{APPROACH_FRACTION * 100:g}% speed{chr(10) + result if result else ''}"

    def _approach(self, stop: Stop) -> tuple[n.Motion, str] | None:
        """A slow MOVE to the target of the motion statement before `stop` in the main program, in its context."""
        stops = self.editor.stops
        before = [s for s in stops[:stops.index(stop)] if not s.end and s.routine is None
                  and isinstance(s.statement, n.Motion) and s.statement.target is not None]
        if not before:
            return None
        last = before[-1]
        stmt = last.statement
        slow = n.With(n.Name("SPEED"), n.Number(f"{APPROACH_FRACTION * 100:g}%"))
        return n.Motion("MOVE", stmt.tool, (n.To(stmt.target), slow), span=stmt.span), last.frame

    def back(self) -> str:
        """The previous motion in reverse (slowly), and the program pointer back to its statement."""
        history = self.robot.history
        if not history:
            raise EditError(":back: no motion to go back over")
        execution = self.execution
        execution.refuse_if_busy()
        done = history.pop()
        layer = self.robot.layer
        tool = None if done.tool is None or done.tool == Pose(0.0, 0.0, 0.0) else done.tool.matrix()
        if done.kind == "linear":
            target = Pose.from_matrix(layer.fk(np.array(done.q_start_rad), tool))
            handle = layer.move(CartesianMotion(target=target, kind="linear", tool=tool),
                                Params(speed_m_s=BACK_TCP_SPEED_M_S * execution.override))
        else:
            handle = layer.move(JointMotion(target_rad=done.q_start_rad, tool=tool),
                                Params(speed_fraction=APPROACH_FRACTION * execution.override))
        if handle.status is MoveStatus.FAULT:
            history.append(done)
            raise EditError(f":back: {handle.error}")
        editor = self.editor
        target_stop = next((s for s in editor.stops if s.line == done.line and not s.end and s.routine is None), None)

        def job() -> Iterator[object]:
            while not handle.done:
                self.robot.tick()
                yield None
            if target_stop is not None:
                point_at(execution.executive(), editor.program, target_stop)
                editor.goto(done.line, quiet=True)
                execution.notify(f"back over {done.keyword}; program pointer at line {done.line}")
            else:
                execution.notify(f"back over {done.keyword}")
        return execution.start("back", job())
