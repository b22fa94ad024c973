"""The session's jogging: `:jog` commands and the jog keys (space, axis, increment) sent to the motion layer."""

from __future__ import annotations

import time
from typing import TYPE_CHECKING

import numpy as np

from orc_rpl.errors import OrcError
from orc_rpl.executive.signals import RunError
from orc_rpl.motion import MoveStatus
from orc_rpl.pendant.jog import CARTESIAN_AXES, CONTINUOUS, STEPS, Jog, JogError, jog_motion, jog_params, parse_amount
from orc_rpl.pendant.robot import Done
from orc_rpl.syntax import nodes as n

if TYPE_CHECKING:
    from orc_rpl.pendant.session import PendantSession

#: The coordinate systems the jog keys cycle through (F2 in jog mode).
SPACES = ("joint", "world", "tool", "frame")


class JoggingMixin:
    """Jog commands; every jog is one motion-layer move from where the robot will be."""

    def _init_jogging(self: PendantSession) -> None:
        self.jog_space = "joint"
        self.jog_axis = 0                 #: index into the joints or CARTESIAN_AXES
        self.jog_increment = 0            #: index into STEPS; len(STEPS) is continuous jogging
        self.jog_frame = "world"
        self.last_jog_sent_s = 0.0        #: perf_counter() when the last jog reached the motion layer

    def jog(self: PendantSession, space: str, axis: str, amount: str, frame: str | None = None) -> str:
        """`:jog joint 3 +5deg`, `:jog world x +10mm`, `:jog tool z -2mm`, `:jog frame base_plate y +1mm`."""
        if space not in SPACES:
            raise JogError(f":jog: unknown space {space!r}; use joint, world, tool or frame NAME")
        axis = axis.lower()
        if space == "joint":
            if not axis.isdigit():
                raise JogError(f":jog joint: the axis is a joint number (1-6), got {axis!r}")
            rotation = True
        elif axis not in CARTESIAN_AXES:
            raise JogError(f":jog {space}: unknown axis {axis!r}; use x, y, z, rx, ry or rz")
        else:
            rotation = axis.startswith("r")
        value = parse_amount(amount, rotation)
        self._send(Jog(space, axis, value, frame or "world"))
        return self.event(f"jog {space}{' ' + frame if frame else ''} {axis} {amount}")

    def jog_key(self: PendantSession, sign: int) -> str:
        """A jog key: the selected axis, one increment (or, continuous, a little more motion while keys repeat)."""
        continuous = self.jog_increment >= len(STEPS)
        _, length_m, angle_rad = CONTINUOUS if continuous else STEPS[self.jog_increment]
        if continuous and self.robot.pending() > 1:
            return ""  # keyboard auto-repeat faster than the robot: let the queued motion run first
        axis = str(self.jog_axis + 1) if self.jog_space == "joint" else CARTESIAN_AXES[self.jog_axis]
        rotation = self.jog_space == "joint" or axis.startswith("r")
        frame = self.jog_frame if self.jog_space == "frame" else "world"
        self._send(Jog(self.jog_space, axis, sign * (angle_rad if rotation else length_m), frame))
        return ""

    def cycle_jog_space(self: PendantSession) -> str:
        """joint -> world -> tool -> frame (the FRAME block at the cursor) -> joint."""
        self.jog_space = SPACES[(SPACES.index(self.jog_space) + 1) % len(SPACES)]
        if self.jog_space == "frame":
            from orc_rpl.pendant.editing import context_of

            self.jog_frame = context_of(self.at_cursor)[1] if self.stops else "world"
        self.jog_axis = min(self.jog_axis, 5)
        return f"jog in {self.jog_label()}"

    def cycle_jog_increment(self: PendantSession) -> str:
        self.jog_increment = (self.jog_increment + 1) % (len(STEPS) + 1)
        return f"jog increment {self.increment_label()}"

    def select_jog_axis(self: PendantSession, delta: int) -> str:
        count = len(self.robot.joints()) if self.jog_space == "joint" else len(CARTESIAN_AXES)
        self.jog_axis = (self.jog_axis + delta) % count
        return f"jog axis {self.axis_label()}"

    def jog_label(self: PendantSession) -> str:
        return f"frame {self.jog_frame}" if self.jog_space == "frame" else self.jog_space

    def axis_label(self: PendantSession) -> str:
        return f"J{self.jog_axis + 1}" if self.jog_space == "joint" else CARTESIAN_AXES[self.jog_axis]

    def increment_label(self: PendantSession) -> str:
        return CONTINUOUS[0] if self.jog_increment >= len(STEPS) else STEPS[self.jog_increment][0]

    def _send(self: PendantSession, jog: Jog) -> None:
        if self.job is not None:
            raise JogError(f"busy: {self.job_name} is running (:stop stops it)")
        layer = self.robot.layer
        frame_world = np.eye(4)
        tool_pose = self.tool_pose()
        if jog.space == "frame" and jog.frame != "world":
            declared = self.declared().get(jog.frame)
            if not (isinstance(declared, n.Declaration) and declared.kind == "FRAME"):
                raise JogError(f":jog frame {jog.frame}: not a declared FRAME")
            try:
                frame_world = self.executive().machine.frame_matrix(jog.frame)
            except RunError as error:
                raise JogError(f":jog frame {jog.frame}: {error.message}") from None
        tool = None if tool_pose is None else tool_pose.matrix()
        try:
            motion = jog_motion(layer, jog, tool, frame_world)
            q_start = tuple(float(v) for v in layer.planned_end_q())
            self.last_jog_sent_s = time.perf_counter()
            handle = layer.move(motion, jog_params(jog, self.override))
        except OrcError as error:
            raise JogError(f"jog refused, nothing moved: {error}") from None
        if handle.status in (MoveStatus.FAULT, MoveStatus.ILLEGAL):
            raise JogError(f"jog refused, nothing moved: {handle.error or handle.status.value}")
        self.robot.remember(Done(q_start, "joint" if jog.space == "joint" else "linear", tool_pose, 0, "jog"))
        if self.synchronous:
            self.robot.run_until_idle()
