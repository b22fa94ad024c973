"""A robot without physics for tests: records every motion request, moves in a nominal time, IO as plain arrays."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from orc_rpl.application.runtime import FunctionParam, MotionRequest, MotionView
from orc_rpl.errors import Unreachable
from orc_rpl.plant.io import CellIO
from orc_rpl.world.pose import Joints, Pose

#: Where the flange starts: in front of the robot, pointing down.
HOME_FLANGE = Pose(1.0, 0.0, 0.9, 0.0, math.pi, 0.0)


@dataclass(slots=True)
class RecordedMotion:
    """One request as the recording robot saw it."""

    request: MotionRequest
    submitted_s: float             #: controller time of the submission
    pending_before: int            #: motions still running then (1: it was given while another ran, to blend)


@dataclass(eq=False, slots=True)
class Ticket:
    """A motion in the recording robot's queue."""

    request: MotionRequest
    duration_s: float
    start: np.ndarray | None = None          #: flange at the start (4x4), set when it starts
    end: np.ndarray | None = None            #: flange at the end
    elapsed_s: float = 0.0
    done: bool = False
    outcome: str = "running"
    error: Exception | None = None
    s: float = 0.0
    joints_end: tuple[float, ...] | None = field(default=None)


class RecordingRobot:
    """Implements RobotInterface with straight-line interpolation and no dynamics; deterministic and fast.

    A Cartesian target farther than `reach_m` from the base raises Unreachable when submitted (a rough
    sphere: 1.8 m, beyond the 1.55 m of the default arm's wrist plus a tool); a joint
    target leaves the TCP where it was (there is no kinematic model here).
    """

    def __init__(self, dt_s: float = 0.004, reach_m: float = 1.8, default_speed_m_s: float = 1.0,
                 min_duration_s: float = 0.1, n_joints: int = 6) -> None:
        self.dt_s = dt_s
        self.io = CellIO()
        self.reach_m = reach_m
        self.default_speed_m_s = default_speed_m_s
        self.min_duration_s = min_duration_s
        self.recorded: list[RecordedMotion] = []
        self.stops = 0
        self._steps = 0
        self._flange = HOME_FLANGE.matrix()
        self._joints = tuple(0.0 for _ in range(n_joints))
        self._queue: list[Ticket] = []

    # -- RobotInterface ----------------------------------------------------------------

    def time_s(self) -> float:
        return self._steps * self.dt_s

    def tick(self) -> None:
        self._steps += 1
        now = self.time_s()
        self.io.update(now)
        if not self._queue:
            return
        ticket = self._queue[0]
        if ticket.start is None:
            self._begin(ticket)
        ticket.elapsed_s += self.dt_s
        ticket.s = min(1.0, ticket.elapsed_s / ticket.duration_s)
        self._flange = self._interpolate(ticket)
        until = ticket.request.until
        if until is not None and until(MotionView(now, ticket.s)):
            self._finish(ticket, "stopped")
        elif ticket.s >= 1.0:
            self._finish(ticket, "reached")

    def submit(self, request: MotionRequest) -> Ticket:
        for point in (request.target if type(request.target) is not FunctionParam else None, *request.via):
            if type(point) is Pose and math.dist((point.x, point.y, point.z), (0.0, 0.0, 0.0)) > self.reach_m:
                raise Unreachable(f"target ({point.x:.4f}, {point.y:.4f}, {point.z:.4f}) m is out of reach "
                                  f"({self.reach_m} m from the base)")
        self.recorded.append(RecordedMotion(request, self.time_s(), self.pending()))
        ticket = Ticket(request, self._duration(request))
        self._queue.append(ticket)
        return ticket

    def pending(self) -> int:
        return len(self._queue)

    def stop(self) -> None:
        self.stops += 1
        for ticket in list(self._queue):
            self._finish(ticket, "stopped")

    def tcp_pose(self, tool: Pose | None) -> Pose:
        t = self._flange if tool is None else self._flange @ tool.matrix()
        return Pose.from_matrix(t)

    def joints(self) -> tuple[float, ...]:
        return self._joints

    def torques(self) -> tuple[float, ...]:
        return tuple(0.0 for _ in self._joints)

    def position_error_m(self) -> float:
        return 0.0

    def thermal_loads(self) -> tuple[float, ...]:
        return tuple(0.0 for _ in self._joints)  # no torques, no heat

    # -- motion model ------------------------------------------------------------------

    def _target_flange(self, request: MotionRequest, s: float = 1.0) -> np.ndarray:
        target = request.target
        if type(target) is Joints:
            return self._flange
        pose = target.fn(s) if isinstance(target, FunctionParam) else target
        return pose.matrix() @ np.linalg.inv(request.tool.matrix())

    def _duration(self, request: MotionRequest) -> float:
        if request.time_s:
            return max(request.time_s, self.dt_s)
        start = self._queue[-1].end if self._queue and self._queue[-1].end is not None else self._flange
        distance = float(np.linalg.norm(self._target_flange(request)[:3, 3] - start[:3, 3]))
        speed = request.speed_m_s if isinstance(request.speed_m_s, (int, float)) else self.default_speed_m_s
        fraction = request.speed_fraction if isinstance(request.speed_fraction, (int, float)) else 1.0
        return max(self.min_duration_s, distance / (speed * fraction))

    def _begin(self, ticket: Ticket) -> None:
        ticket.start = self._flange.copy()
        ticket.end = self._target_flange(ticket.request)
        if type(ticket.request.target) is Joints:
            ticket.joints_end = ticket.request.target.values

    def _interpolate(self, ticket: Ticket) -> np.ndarray:
        assert ticket.start is not None and ticket.end is not None
        if isinstance(ticket.request.target, FunctionParam):  # a path in function space: follow the function
            return self._target_flange(ticket.request, ticket.s)
        t = ticket.end.copy()
        t[:3, 3] = ticket.start[:3, 3] + ticket.s * (ticket.end[:3, 3] - ticket.start[:3, 3])
        return t

    def _finish(self, ticket: Ticket, outcome: str) -> None:
        ticket.done, ticket.outcome = True, outcome
        if ticket.joints_end is not None and outcome == "reached":
            self._joints = ticket.joints_end
        self._queue.remove(ticket)
