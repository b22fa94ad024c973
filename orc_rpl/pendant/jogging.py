"""The pendant's jogger: `:jog` commands and the jog keys (space, axis, increment), each jog one motion-layer move."""

from __future__ import annotations

import time

import numpy as np

from orc_rpl.errors import OrcError
from orc_rpl.executive.signals import RunError
from orc_rpl.motion import MoveStatus
from orc_rpl.pendant.editing import Editor
from orc_rpl.pendant.events import EventLog
from orc_rpl.pendant.execution import Execution
from orc_rpl.pendant.jog import CARTESIAN_AXES, CONTINUOUS, STEPS, Jog, JogError, jog_motion, jog_params, parse_amount
from orc_rpl.pendant.robot import Done, PendantRobot
from orc_rpl.syntax import nodes as n

#: The coordinate systems the jog keys cycle through (F2 in jog mode).
SPACES = ("joint", "world", "tool", "frame")


class Jogger:
    """Owns the jog settings; every jog is one move from where the robot will be, with the execution's tool."""

    def __init__(self, editor: Editor, execution: Execution, robot: PendantRobot, events: EventLog) -> None:
        self.editor = editor
        self.execution = execution
        self.robot = robot
        self.events = events
        self.space = "joint"
        self.axis = 0                     #: index into the joints or CARTESIAN_AXES
        self.increment = 0                #: index into STEPS; len(STEPS) is continuous jogging
        self.frame = "world"
        self.last_sent_s = 0.0            #: perf_counter() when the last jog reached the motion layer

    def jog(self, space: str, axis: str, amount: str, frame: str | None = None) -> str:
        """`:jog joint 3 +5deg`, `:jog world x +10mm`, `:jog tool z -2mm`, `:jog frame base_plate y +1mm`.

        The jog keys go on from here: the space, axis and frame typed become the ones the keys jog and the
        state pane shows.
        """
        if space == "axis":
            return self.jog_axis(axis, amount)
        if space not in SPACES:
            raise JogError(f":jog: unknown space {space!r}; use joint, world, tool, frame NAME or axis NAME")
        axis = axis.lower()
        if space == "joint":
            if not axis.isdigit():
                raise JogError(f":jog joint: the axis is a joint number (1-6), got {axis!r}")
            rotation = True
            index = int(axis) - 1  # a joint the robot lacks is refused by the jog move below
        elif axis not in CARTESIAN_AXES:
            raise JogError(f":jog {space}: unknown axis {axis!r}; use x, y, z, rx, ry or rz")
        else:
            rotation = axis.startswith("r")
            index = CARTESIAN_AXES.index(axis)
        value = parse_amount(amount, rotation)
        self._send(Jog(space, axis, value, frame or "world"))
        self.space, self.axis = space, index
        if space == "frame":
            self.frame = frame or "world"
        return self.events.record(f"jog {space}{' ' + frame if frame else ''} {axis} {amount}")

    def jog_axis(self, name: str, amount: str) -> str:
        """`:jog axis turn +10deg`: an external axis of the cell (a track, a positioner) moves alone, the arm stands."""
        cell_axes = getattr(getattr(self.robot, "cell", None), "axes", None)
        external = None if cell_axes is None else cell_axes.external
        if external is None:
            raise JogError(":jog axis: this cell has no external axes (a world with a track or a positioner)")
        if name not in external.limits:
            raise JogError(f":jog axis: no external axis {name!r}; the cell has {', '.join(external.limits)}")
        if self.execution.job is not None:
            raise JogError(f"busy: {self.execution.job_name} is running (:stop stops it)")
        axis = cell_axes.world.object(name).axis
        target = external.planned[name] + parse_amount(amount, axis.rotary)
        why = axis.clamp_message(target)
        if why is not None:
            raise JogError(f"jog refused, nothing moved: axis {name}: {why}")
        self.last_sent_s = time.perf_counter()
        external.move_alone(None, {name: target})
        if self.execution.synchronous:
            while external.solo is not None:
                self.robot.tick()
        return self.events.record(f"jog axis {name} {amount}")

    def jog_key(self, sign: int) -> str:
        """A jog key: the selected axis, one increment (or, continuous, a little more motion while keys repeat)."""
        continuous = self.increment >= len(STEPS)
        _, length_m, angle_rad = CONTINUOUS if continuous else STEPS[self.increment]
        if continuous and self.robot.pending() > 1:
            return ""  # keyboard auto-repeat faster than the robot: let the queued motion run first
        axis = str(self.axis + 1) if self.space == "joint" else CARTESIAN_AXES[self.axis]
        rotation = self.space == "joint" or axis.startswith("r")
        frame = self.frame if self.space == "frame" else "world"
        self._send(Jog(self.space, axis, sign * (angle_rad if rotation else length_m), frame))
        return ""

    def cycle_space(self) -> str:
        """joint -> world -> tool -> frame (the FRAME block at the cursor) -> joint."""
        self.space = SPACES[(SPACES.index(self.space) + 1) % len(SPACES)]
        if self.space == "frame":
            self.frame = self.editor.context()[1]
        self.axis = min(self.axis, 5)
        return f"jog in {self.space_label()}"

    def cycle_increment(self) -> str:
        self.increment = (self.increment + 1) % (len(STEPS) + 1)
        return f"jog increment {self.increment_label()}"

    def select_axis(self, delta: int) -> str:
        count = len(self.robot.joints()) if self.space == "joint" else len(CARTESIAN_AXES)
        self.axis = (self.axis + delta) % count
        return f"jog axis {self.axis_label()}"

    def space_label(self) -> str:
        return f"frame {self.frame}" if self.space == "frame" else self.space

    def axis_label(self) -> str:
        return f"J{self.axis + 1}" if self.space == "joint" else CARTESIAN_AXES[self.axis]

    def increment_label(self) -> str:
        return CONTINUOUS[0] if self.increment >= len(STEPS) else STEPS[self.increment][0]

    def _send(self, jog: Jog) -> None:
        execution = self.execution
        if execution.job is not None:
            raise JogError(f"busy: {execution.job_name} is running (:stop stops it)")
        layer = self.robot.layer
        frame_world = np.eye(4)
        tool_pose = execution.tool_pose()
        if jog.space == "frame" and jog.frame != "world":
            declared = self.editor.declared().get(jog.frame)
            if not (isinstance(declared, n.Declaration) and declared.kind == "FRAME"):
                raise JogError(f":jog frame {jog.frame}: not a declared FRAME")
            try:
                frame_world = execution.executive().machine.frame_matrix(jog.frame)
            except RunError as error:
                raise JogError(f":jog frame {jog.frame}: {error.message}") from None
        tool = None if tool_pose is None else tool_pose.matrix()
        cell_axes = getattr(getattr(self.robot, "cell", None), "axes", None)
        if cell_axes is not None:  # a frame of the program's world, seen from the base the track carries
            frame_world = np.linalg.inv(cell_axes.base(cell_axes.planned())) @ frame_world
        try:
            motion = jog_motion(layer, jog, tool, frame_world)
            q_start = tuple(float(v) for v in layer.planned_end_q())
            self.last_sent_s = time.perf_counter()
            handle = layer.move(motion, jog_params(jog, execution.override))
        except OrcError as error:
            raise JogError(f"jog refused, nothing moved: {error}") from None
        if handle.status in (MoveStatus.FAULT, MoveStatus.ILLEGAL):
            raise JogError(f"jog refused, nothing moved: {handle.error or handle.status.value}")
        self.robot.remember(Done(q_start, "joint" if jog.space == "joint" else "linear", tool_pose, 0, "jog"))
        if execution.synchronous:
            self.robot.run_until_idle()
