"""The run-time seam between the executive and the motion core: motion requests, tickets and the RobotInterface protocol."""

from __future__ import annotations

from collections.abc import Callable, Generator
from dataclasses import dataclass, field
from typing import Any, Protocol

from orc_rpl.errors import OrcError
from orc_rpl.world.pose import Joints, Pose

class Fine:
    """The zone value `FINE`: stop exactly at the target."""

    __slots__ = ()

    def __repr__(self) -> str:
        return "FINE"


FINE = Fine()

#: A parameter that may vary along the motion: a number, or a function of the path coordinate s in [0, 1].
Varying = float | Callable[[float], float]


@dataclass(frozen=True, slots=True)
class MotionView:
    """What an UNTIL condition or a function parameter sees in one motion cycle (read-only)."""

    time_s: float          #: controller time
    s: float               #: path coordinate of the move, 0..1
    sensors: Any = None    #: the installed sensors' values this cycle (name -> value), when the robot has sensors


@dataclass(frozen=True, slots=True)
class MotionRequest:
    """One motion as the application layer hands it to the robot: everything in world coordinates and SI units."""

    keyword: str                                  #: MOVE, LMOVE, ... (for messages)
    kind: str                                     #: "joint", "linear", "circular" or "function" (a path in function space)
    target: Pose | Joints | FunctionParam         #: world pose of the TCP, joint angles, or a world pose function of s
    via: tuple[Pose | Joints, ...] = ()           #: via points (CMOVE: the circle's auxiliary point)
    tool: Pose = field(default_factory=lambda: Pose(0.0, 0.0, 0.0))  #: flange -> TCP
    speed_m_s: Varying | None = None              #: TCP speed limit (None: the joints' limits only)
    speed_fraction: Varying = 1.0                 #: fraction of the joint speed limits
    accel_fraction: float = 1.0                   #: fraction of the joint acceleration limits
    zone_m: float = 0.0                           #: blend radius, 0 = FINE
    time_s: float | None = None                   #: requested duration
    load_kg: float = 0.0                          #: payload
    tuning: Any = None                            #: servo tuning (passed down)
    path_control: bool | None = None              #: path velocity control for this motion (None: the robot's setting)
    until: Callable[[MotionView], bool] | None = None  #: stop on the path when it becomes true
    short: bool = False                           #: a short move (ShortMove: jerk-limited, FINE) when the robot has one
    #: a quiet start: averaged over the elastic gears' whole periods even where the robot scales the averaging
    #: to each move's steps (no torque step left inside a recording or a seam's first millimetres)
    whole_averaging: bool = False
    signal_before_end_s: float | None = None      #: tau: the ticket's `signalled_s` is set when t >= T_d - tau
    record_s: float = 0.0                         #: record (t, q, qd, torque) for this long after the start
    #: path correction (TRACKMOVE), called every motion cycle: the TCP offset (world, m) from the planned path
    #: to apply from the next cycle on, or None to stop the motion on its path (the sensor lost the seam)
    correction: Callable[[MotionView], tuple[float, float, float] | None] | None = None
    #: the correction reaches the servo as a smooth trajectory where the motion layer smooths (elastic gears), not
    #: as a step each cycle (TRACKMOVE, whose Tracker models the smoothing; a force loop wants its steps)
    smooth_correction: bool = False
    #: external-axis targets (m or rad) the axes reach with the arm, in the same path coordinate (AXES(p, ...))
    axes: tuple[tuple[str, float], ...] = ()
    #: coordinated motion: the world pose of the target's frame (on a moving frame) for given axis values
    frame_of: Callable[[dict[str, float]], Pose] | None = None
    target_in_frame: Pose | None = None           #: the target relative to that frame
    #: how well the program knows the motion (KNOWN): "completely" and "almost" known motions are planned ahead,
    #: "almost" and "partly" leave part of the limits to sensor corrections, "not" is generated at run time
    known: str = "completely"


class MoveTicket(Protocol):
    """The executive's handle on a submitted motion."""

    @property
    def done(self) -> bool: ...

    @property
    def outcome(self) -> str:
        """"running", "reached", "stopped" (by UNTIL or a stop) or "fault"."""
        ...

    @property
    def error(self) -> Exception | None: ...

    #: controller time when t >= T_d - signal_before_end_s first held (None: not yet, or not asked for)
    signalled_s: float | None
    #: samples recorded during the first `record_s` of the motion
    recording: list[Sample]


@dataclass(frozen=True, slots=True)
class Sample:
    """One motion cycle recorded for the application layer (MotionRequest.record_s)."""

    time_s: float
    q: tuple[float, ...]           #: measured joint angles, rad
    qd: tuple[float, ...]          #: measured joint velocities, rad/s
    torque: tuple[float, ...]      #: joint torques, N m


class IOBanks(Protocol):
    """The cell's IO: banks named DigIn, DigOut, AnaIn, AnaOut, indexed from 1 (plant.io.CellIO)."""

    def bank(self, name: str) -> Any: ...


class RobotInterface(Protocol):
    """What the executive needs from a robot: submit motions, advance time, read the TCP, the joints and the IO."""

    dt_s: float                 #: one motion cycle
    io: IOBanks

    def time_s(self) -> float:
        """The controller clock (simulated time on the virtual robot)."""
        ...

    def tick(self) -> None:
        """Advance one motion cycle."""
        ...

    def submit(self, request: MotionRequest) -> MoveTicket:
        """Plan and start (or queue, to blend) a motion; raises Unreachable/JointLimit/PlanningError when it cannot."""
        ...

    def pending(self) -> int:
        """Motions not yet finished."""
        ...

    def stop(self) -> None:
        """Stop every motion on its path (decelerating), cancelling queued ones."""
        ...

    def tcp_pose(self, tool: Pose | None) -> Pose:
        """The measured TCP pose of `tool` (None: the flange), world frame."""
        ...

    def joints(self) -> tuple[float, ...]:
        """Measured joint angles (rad)."""
        ...

    def torques(self) -> tuple[float, ...]:
        """Joint torques (N m)."""
        ...

    def position_error_m(self) -> float:
        """Distance between the commanded and the measured TCP position (m)."""
        ...

    def thermal_loads(self) -> tuple[float, ...]:
        """Thermal load of each motor estimated from its torque, 1.0 = its continuous limit (ROBOT.Thermal)."""
        ...

    def inverse_dynamics(self, q: tuple[float, ...], qd: tuple[float, ...], qdd: tuple[float, ...],
                         load_kg: float) -> tuple[float, ...]:
        """The controller's robot model: joint torques (N m) for a motion state with `load_kg` at the flange."""
        ...


#: A keyword's `execute(call)` returns a MotionRequest, a list of them, or a procedure: a generator that yields
#: a MotionRequest (the executive submits it and sends back its ticket) or None (one motion cycle passes), and
#: returns when the statement is done (WELDMOVE: move, close the gun tau early, wait for the weld, open).
Procedure = Generator[Any, Any, None]


@dataclass(slots=True)
class MotionCall:
    """A motion statement evaluated by the executive, handed to the keyword's `execute` behaviour."""

    keyword: str
    target: Pose | Joints | FunctionParam | None  #: TO, in world coordinates (None for ALONG); a FUNC of s gives world poses
    path: tuple[Pose | Joints, ...] | None        #: ALONG, in world coordinates
    via: tuple[Pose | Joints, ...]                #: VIA points, in world coordinates
    tool: Pose                                    #: flange -> TCP
    attributes: dict[str, Any]                    #: WITH values by canonical name; FUNCs already made callables
    until: Callable[[MotionView], bool] | None
    speed_override: float = 1.0                   #: `--speed-override`, 0 < f <= 1
    warn: Callable[[str], None] = lambda message: None  #: a warning about this statement (shown once)
    equipment: Any = None                         #: behaviour object of the installed equipment used as the tool
    robot: RobotInterface | None = None           #: the robot (time, TCP, IO) for behaviours that run as procedures
    #: motions with output bindings (IDENTMOVE): the target evaluated once the bindings are known; `target` is None
    resolve_target: Callable[[dict[str, Any]], Pose | Joints] | None = None
    #: call a FUNC of the program given as a value (IDENT's proc) with arguments, in the motion's context
    call_function: Callable[[Any, list[Any]], Any] | None = None


class BehaviourError(OrcError):
    """A behaviour refused its arguments; the executive reports the message at the statement."""


@dataclass(slots=True)
class InstallContext:
    """What an INSTALL kind's factory gets: the object's name, its WITH attributes and the cell's IO."""

    name: str
    kind: str
    attributes: dict[str, Any]                    #: canonical attribute names; IO channels as IOChannel values
    read: Callable[[Any], Any]                    #: read an IO channel (digital: 0/1)
    write: Callable[[Any, Any], None]             #: write an IO channel
    robot: RobotInterface


@dataclass(frozen=True, slots=True)
class FunctionParam:
    """An attribute given as a FUNC name: `fn(s)` gives the RPL value at path coordinate s in [0, 1]; a target
    given as a FUNC of `t` (`variable` "t") gives the pose t seconds after the motion's start."""

    name: str
    fn: Callable[[float], Any]
    variable: str = "s"


def attached(robot: Any, name: str, make: Callable[[], Any]) -> Any:
    """The robot's `name` (its sensor manager, its process record), made with `make()` and kept on it on first use."""
    value = getattr(robot, name, None)
    if value is None:
        value = make()
        try:
            setattr(robot, name, value)
        except AttributeError:  # a robot without attributes of its own keeps none
            pass
    return value


def run_to_end(robot: RobotInterface, request: MotionRequest, timeout_s: float, what: str) -> Any:
    """Submit one motion and run the robot until it ends, for functions that move it (RecordSeam, CALIBRATE).

    A motion still running after `timeout_s` of controller time is stopped on its path and reported;
    a motion that faulted raises its error. Returns the ticket (its recording, its outcome).
    """
    ticket = robot.submit(request)
    deadline = robot.time_s() + timeout_s
    while not ticket.done:
        robot.tick()
        if robot.time_s() > deadline:
            robot.stop()
            raise BehaviourError(f"{what}: a motion did not end within {timeout_s:g} s")
    if ticket.outcome == "fault":
        raise ticket.error if ticket.error is not None else BehaviourError(f"{what}: a motion failed")
    return ticket

