"""Moving the program pointer and going back: :pp with its approach motion, and :back over the last motion."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

import numpy as np

from orc_rpl.motion import CartesianMotion, JointMotion, MoveStatus, Params
from orc_rpl.pendant.adapter import point_at
from orc_rpl.pendant.tree import EditError, Stop
from orc_rpl.syntax import nodes as n
from orc_rpl.world.pose import Pose

if TYPE_CHECKING:
    from orc_rpl.pendant.session import PendantSession

#: :pp's approach motion and :back run at this fraction of the robot's speed (times the override).
APPROACH_FRACTION = 0.1
#: :back along a straight line runs at this TCP speed (times the override).
BACK_TCP_SPEED_M_S = 0.1


class PointerMixin:
    """The program pointer set anywhere, safely; the robot taken back over its motions."""

    def pp(self: PendantSession) -> str:
        """Program pointer to the cursor; then a slow joint motion to where the statement starts (the end of the
        motion before it), so that :run or :step go on exactly as the program would."""
        stop = self.at_cursor
        ex = self.executive()
        status = point_at(ex, self.program, stop)
        if status != "paused":
            return self.event("program pointer at the end of the program")
        message = self.event(f"program pointer at line {ex.pointer.line}")
        approach = self._approach(stop)
        if approach is None:
            return message
        previous, frame = approach
        result = self._statement_job("approach", previous, None, frame, 0, None, quiet=True)
        return f"{message}; approach to the end of line {previous.span.line}'s motion at " \
               f"{APPROACH_FRACTION * 100:g}% speed{chr(10) + result if result else ''}"

    def _approach(self: PendantSession, stop: Stop) -> tuple[n.Motion, str] | None:
        """A slow MOVE to the target of the motion statement before `stop` in the main program, in its context."""
        before = [s for s in self.stops[:self.stops.index(stop)] if not s.end and s.routine is None
                  and isinstance(s.statement, n.Motion) and s.statement.target is not None]
        if not before:
            return None
        last = before[-1]
        stmt = last.statement
        slow = n.With(n.Name("SPEED"), n.Number(f"{APPROACH_FRACTION * 100:g}%"))
        return n.Motion("MOVE", stmt.tool, (n.To(stmt.target), slow), span=stmt.span), last.frame

    def back(self: PendantSession) -> str:
        """The previous motion in reverse (slowly), and the program pointer back to its statement."""
        history = self.robot.history
        if not history:
            raise EditError(":back: no motion to go back over")
        if self.job is not None:
            raise EditError(f"busy: {self.job_name} is running (:stop stops it)")
        done = history.pop()
        layer = self.robot.layer
        tool = None if done.tool is None or done.tool == Pose(0.0, 0.0, 0.0) else done.tool.matrix()
        if done.kind == "linear":
            target = Pose.from_matrix(layer.fk(np.array(done.q_start_rad), tool))
            handle = layer.move(CartesianMotion(target=target, kind="linear", tool=tool),
                                Params(speed_m_s=BACK_TCP_SPEED_M_S * self.override))
        else:
            handle = layer.move(JointMotion(target_rad=done.q_start_rad, tool=tool),
                                Params(speed_fraction=APPROACH_FRACTION * self.override))
        if handle.status is MoveStatus.FAULT:
            history.append(done)
            raise EditError(f":back: {handle.error}")
        target_stop = next((s for s in self.stops if s.line == done.line and not s.end and s.routine is None), None)

        def job() -> Iterator[object]:
            while not handle.done:
                self.robot.tick()
                yield None
            if target_stop is not None:
                point_at(self.executive(), self.program, target_stop)
                self.goto(done.line, quiet=True)
                self._notify(f"back over {done.keyword}; program pointer at line {done.line}")
            else:
                self._notify(f"back over {done.keyword}")
        return self._start("back", job())
