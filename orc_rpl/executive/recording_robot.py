"""A robot without physics for tests: records every motion request, moves in a nominal time, IO as plain arrays."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from orc_rpl.application.runtime import FunctionParam, MotionRequest, MotionView, Sample
from orc_rpl.errors import Unreachable
from orc_rpl.plant.io import CellIO
from orc_rpl.world.pose import Joints, Pose

#: Where the flange starts: in front of the robot, pointing down.
HOME_FLANGE = Pose(1.0, 0.0, 0.9, 0.0, math.pi, 0.0)


#: The recording robot's torque model: the arm's own weight (kg m) and the payload's lever (m) on each joint.
ARM_GRAVITY_KG_M = (0.0, 60.0, 20.0, 0.0, 1.0, 0.0)
LOAD_LEVER_M = (0.0, 1.0, 0.8, 0.0, 0.1, 0.0)


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
    signalled_s: float | None = None         #: when t >= T_d - tau first held (request.signal_before_end_s)
    recording: list[Sample] = field(default_factory=list)  #: the first record_s of the motion


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
        self.payload_kg = 0.0          #: the plant's payload (a part in the gripper), seen in the torques
        self.last_tool: Pose | None = None  #: the tool of the last motion submitted (where a sensor looks)
        self.sensors = _sensor_manager(self)
        self._offset = np.zeros(3)     #: a tracked motion's path correction (world, m)

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
        request = ticket.request
        if request.correction is not None:
            offset = request.correction(MotionView(now, ticket.s, self.sensors.readings.new_cycle(self._steps)))
            if offset is None:
                self._finish(ticket, "stopped")
                return
            self._offset = np.asarray(offset, dtype=float)
            self._flange[:3, 3] += self._offset
        tau = request.signal_before_end_s
        if tau is not None and ticket.signalled_s is None and ticket.elapsed_s >= ticket.duration_s - tau - 1e-9:
            ticket.signalled_s = now
        if request.record_s > 0 and ticket.elapsed_s <= request.record_s + 1e-9:
            ticket.recording.append(Sample(now, self._joints, tuple(0.0 for _ in self._joints), self.torques()))
        until = ticket.request.until
        if until is not None and until(MotionView(now, ticket.s)):
            self._finish(ticket, "stopped")
        elif ticket.s >= 1.0:
            self._finish(ticket, "reached")

    def submit(self, request: MotionRequest) -> Ticket:
        self.last_tool = request.tool
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
        """A toy model without motion: the arm's and the payload's weight on fixed lever arms."""
        return self.inverse_dynamics(self._joints, (), (), self.payload_kg)

    def set_plant_payload(self, mass_kg: float) -> None:
        """Simulation only: a part of `mass_kg` in the gripper, seen in the torques."""
        self.payload_kg = mass_kg

    def inverse_dynamics(self, q: tuple[float, ...], qd: tuple[float, ...], qdd: tuple[float, ...],
                         load_kg: float) -> tuple[float, ...]:
        n = len(q)
        arms, levers = (ARM_GRAVITY_KG_M + (0.0,) * n)[:n], (LOAD_LEVER_M + (0.0,) * n)[:n]
        return tuple(9.81 * (arm + load_kg * lever) for arm, lever in zip(arms, levers))

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
        """The nominal duration; a requested TIME makes the motion take at least that long (as on the cell)."""
        start = self._queue[-1].end if self._queue and self._queue[-1].end is not None else self._flange
        distance = float(np.linalg.norm(self._target_flange(request)[:3, 3] - start[:3, 3]))
        speed = request.speed_m_s if isinstance(request.speed_m_s, (int, float)) else self.default_speed_m_s
        fraction = request.speed_fraction if isinstance(request.speed_fraction, (int, float)) else 1.0
        natural = max(self.min_duration_s, distance / (speed * fraction))
        return max(request.time_s, natural) if request.time_s else natural

    def _begin(self, ticket: Ticket) -> None:
        self._offset = np.zeros(3)
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


def _sensor_manager(robot: Any) -> Any:
    """The robot's sensors, simulated from the cell's process models (the seam) at the last tool's TCP."""
    from orc_rpl.executive.sim_io import simulated_sensors
    from orc_rpl.motion.sensors import SensorManager

    def tcp() -> tuple[float, float, float]:
        pose = robot.tcp_pose(robot.last_tool)
        return (pose.x, pose.y, pose.z)
    return SensorManager(simulated_sensors(robot.io, tcp))
