"""The pendant's robot: the executive's CellRobot seen through a proxy that remembers motions (for :back) and time slices."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from orc_rpl.application.runtime import MotionRequest
from orc_rpl.executive.cell_robot import CellRobot
from orc_rpl.motion import Mode

#: Manual mode caps the TCP speed of every motion, program motions included (docs/pendant.md, modes).
MANUAL_TCP_SPEED_M_S = 0.25
#: How many motions :back can walk back through.
HISTORY_LENGTH = 50


@dataclass(frozen=True, slots=True)
class Done:
    """A motion the robot made: where it started, how it moved, which statement asked for it (0: jog or :back)."""

    q_start_rad: tuple[float, ...]
    kind: str                   #: "joint", "linear" or "circular"
    tool: Any                   #: the Pose of the TCP used
    line: int
    keyword: str


class PendantRobot:
    """A RobotInterface for the executive over a CellRobot, plus what only the pendant needs: the motion history,
    the line of the statement asking (set by the session), a pause after a slice of cycles, submit timestamps."""

    def __init__(self, cell: CellRobot) -> None:
        self.cell = cell
        self.layer = cell.layer
        self.dt_s = cell.dt_s
        self.io = cell.io
        self.history: list[Done] = []
        self.line_source: Callable[[], int] = lambda: 0   #: the line of the statement asking for a motion
        self.ticks = 0
        self.slice_end: int | None = None            #: tick count at which `on_slice_end` is called
        self.on_slice_end: Callable[[], None] | None = None
        self.last_submit_s = 0.0                     #: perf_counter() when the last motion reached the motion layer
        self.mode = "auto"
        self.tick_listeners = cell.tick_listeners    #: the cell's: called after every motion cycle (the 3D view)
        self.asking_line = 0                         #: while a program motion is submitted: its statement's line

    @classmethod
    def virtual(cls, robot: str = "irb2400", backend: str = "servo") -> PendantRobot:
        return cls(CellRobot.virtual(robot=robot, backend=backend))

    # -- RobotInterface, delegated ------------------------------------------------------

    def time_s(self) -> float:
        return self.cell.time_s()

    def tick(self) -> None:
        self.cell.tick()
        self.ticks += 1
        if self.slice_end is not None and self.ticks >= self.slice_end and self.on_slice_end is not None:
            self.on_slice_end()

    def pending(self) -> int:
        return self.cell.pending()

    def stop(self) -> None:
        self.cell.stop()

    def tcp_pose(self, tool: Any) -> Any:
        return self.cell.tcp_pose(tool)

    def joints(self) -> tuple[float, ...]:
        return self.cell.joints()

    def torques(self) -> tuple[float, ...]:
        return self.cell.torques()

    def position_error_m(self) -> float:
        return self.cell.position_error_m()

    def thermal_loads(self) -> tuple[float, ...]:
        return self.cell.thermal_loads()

    def inverse_dynamics(self, q: tuple[float, ...], qd: tuple[float, ...], qdd: tuple[float, ...],
                         load_kg: float) -> tuple[float, ...]:
        return self.cell.inverse_dynamics(q, qd, qdd, load_kg)

    def submit(self, request: MotionRequest) -> Any:
        q_start = tuple(float(v) for v in self.layer.planned_end_q())
        self.last_submit_s = time.perf_counter()
        line = self.line_source()
        self.asking_line = line  # the motion layer's planned-path signal, heard inside submit, learns the statement
        try:
            ticket = self.cell.submit(request)
        finally:
            self.asking_line = 0
        self.remember(Done(q_start, request.kind, request.tool, line, request.keyword))
        return ticket

    # -- the pendant's own -------------------------------------------------------------

    def remember(self, done: Done) -> None:
        self.history.append(done)
        del self.history[:-HISTORY_LENGTH]

    def set_mode(self, mode: str) -> None:
        """manual: every motion planned from now on is capped at 250 mm/s at the TCP; auto: no cap."""
        self.layer.set_speed_cap(MANUAL_TCP_SPEED_M_S if mode == "manual" else None)
        self.mode = mode

    def run_until_idle(self, limit_s: float = 120.0) -> None:
        """Advance time until every motion is done (tests and the synchronous session)."""
        end = self.time_s() + limit_s
        while self.pending() > 0 and self.time_s() < end:
            self.tick()

    def halt(self) -> None:
        """Stop on the path and let the robot come to rest."""
        self.stop()
        self.run_until_idle(10.0)

    def commanded_tcp(self, tool: Any) -> Any:
        """The TCP where the robot is commanded to be (world): what :teach stores, so that moving back to a taught
        position ends exactly there instead of drifting by the servo's steady-state error each time."""
        from orc_rpl.world.pose import Pose

        matrix = None if tool is None else tool.matrix()
        tcp = self.layer.fk(self.layer.reference_q(), matrix)
        axes = getattr(self.cell, "axes", None)
        if axes is not None:  # the track carries the base: where the axes are commanded to be
            tcp = axes.base(axes.planned()) @ tcp
        return Pose.from_matrix(tcp)

    def joints_deg(self) -> tuple[float, ...]:
        return tuple(float(np.degrees(q)) for q in self.joints())

    def servo_mode(self) -> Mode:
        return self.layer.get_mode()

    def snapshot(self, path: str, width: int = 640, height: int = 480) -> str:
        """An offscreen render of the cell (MuJoCo); a UsageError when the backend has no cell or no OpenGL."""
        from orc_rpl.errors import UsageError

        loop = getattr(self.layer.backend, "loop", None)
        if getattr(self.layer.backend, "real_arm", False):
            raise UsageError("a real arm has no simulated cell to render: take a photograph")
        if loop is None:
            raise UsageError("this robot has no simulated cell to render (kinematic backend)")
        return str(loop.cell.render_png(path, width, height))
