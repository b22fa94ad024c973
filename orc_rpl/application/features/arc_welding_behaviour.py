"""Behaviour of arc welding (thesis 2.3, 4.5): RecordSeam, OptimalSpeed, Tracking, TRACKMOVE, SeamLost, ArcWelder.

    EdgeData = RecordSeam(CalibPath)          -- slowly along the path with standard tracking, record the seam
    OptSpeed = OptimalSpeed(EdgeData)         -- a speed from the seam's curvature and raggedness
    OptTrack = Tracking(EdgeData, OptSpeed)   -- the tracking filter for that seam at that speed
    TRACKMOVE torch TO EndPos WITH V = OptSpeed WITH SENSOR = LaserSensor WITH TRACKING = OptTrack

Tracking is a path correction at the motion rate: every motion cycle the laser's lateral offset of the seam
from the TCP, e, added to the correction the servo has been given so far, a, feeds a first-order low-pass
c <- c + g (a + e - c), and the TCP is moved by c along the lateral direction (horizontal, perpendicular to the
straight path) from the next cycle on. On rigid gears a correction is a step (a = c: the integrator c <- c + g e);
on elastic gears the motion layer smooths it (motion.path_offset) and the Tracker runs the same filter for a. The seam counts as
lost (SeamLost, catchable with TRY ... ON SeamLost) when, once found, the laser sees no seam for LOST_CYCLES
cycles, or when it is not found within ACQUIRE_M of the start; the robot stops on its path. A SensorFault of
the laser (a lost link) also stops the robot on its path and is raised at the statement.

The design stages are open and replaceable (plain functions of the recording):
* OptimalSpeed: v = LATERAL_SPEED / slope95 / (1 + raggedness / RAGGED_REF), clamped to [V_MIN, V_MAX] and
  rounded down to 1 mm/s; slope95 is the 95th percentile of |d offset / d s| of the seam's 10 mm mean line
  (the correction must move the torch sideways at slope * v), raggedness the RMS of the seam about that line.
* Tracking: the gain g (per 4 ms cycle) minimising the RMS deviation of the corrected TCP from the seam's
  10 mm mean line, simulated on the recording at that speed with the loop's delay and the smoothing of its
  corrections (the seam's LoopDelay and Smoothing, which RecordSeam took from the robot: `loop_delay_cycles`);
  a high gain passes the raggedness on to the torch, a low one lags behind the curve.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np

from orc_rpl.application.features.gears import lowest_anti_resonance_rad_s, start_averaging_s
from orc_rpl.application.process_log import SeamRecord, process_log
from orc_rpl.application.runtime import (
    BehaviourError, InstallContext, MotionCall, MotionRequest, MotionView, run_to_end,
)
from orc_rpl.application.standard_behaviour import standard_motion
from orc_rpl.application.values import Record
from orc_rpl.errors import MotionFault, SensorFault
from orc_rpl.motion.path_offset import PathOffset, correction_omega_rad_s
from orc_rpl.plant.processes.seam import cell_seam
from orc_rpl.syntax.units import LENGTH, TIME, VELOCITY, Quantity
from orc_rpl.world.pose import Joints, Pose

RECORD_SPEED_M_S = 0.02     #: RecordSeam moves this slowly
STANDARD_GAIN = 0.02        #: RecordSeam's standard (low-gain) tracking, per motion cycle
LATERAL_SPEED_M_S = 0.01    #: the sideways speed the correction may need (OptimalSpeed)
RAGGED_REF_M = 0.001        #: raggedness that halves the speed (OptimalSpeed)
V_MIN_M_S, V_MAX_M_S = 0.01, 0.1
MEAN_LINE_M = 0.01          #: the seam's mean line: its average over this length (about the weld pool)
LOOP_DELAY = 3              #: cycles from a correction to the laser seeing it (one cycle + the servo's lag)
SERVO_STEPS = 4             #: servo steps a motion cycle, over which the motion layer smooths a correction
LOST_CYCLES = 3             #: the seam is lost after this many cycles without it
ACQUIRE_M = 0.015           #: TRACKMOVE must find the seam within this distance of its start
MOTION_TIMEOUT_S = 120.0


class SeamLost(MotionFault):
    """The laser lost the seam during TRACKMOVE."""

    rpl_name = "SeamLost"


class ArcWelder:
    """The welding power source: ARC (a digital output) strikes the arc."""

    def __init__(self, context: InstallContext) -> None:
        self._context = context
        self.arc = context.attributes.get("ARC")
        if self.arc is None:
            raise BehaviourError(f"INSTALL {context.name} AS ArcWelder needs WITH ARC = DigOut[n]")

    def On(self) -> None:  # noqa: N802 - the language's method names
        self._context.write(self.arc, 1)

    def Off(self) -> None:  # noqa: N802
        self._context.write(self.arc, 0)


# -- the geometry of a straight piece and the tracking loop ------------------------------------------------


def lateral_direction(start: Any, end: Any) -> np.ndarray:
    """Horizontal and perpendicular to start -> end (as the seam model's lateral direction)."""
    d = np.asarray(end, float) - np.asarray(start, float)
    lateral = np.cross((0.0, 0.0, 1.0), d)
    n = float(np.linalg.norm(lateral))
    return lateral / n if n > 1e-9 else np.array((1.0, 0.0, 0.0))


class Tracker:
    """The correction loop of one straight motion: c <- c + g (e + a - c) each cycle, a being the correction the
    servo has been given so far (the motion layer's smoothing of c: `applied`); None when the seam is lost. Without
    smoothing (rigid gears) a = c and the loop is the integrator c <- c + g e."""

    def __init__(self, sensor_name: str, lateral: np.ndarray, gain: float, read: Callable[[], Any],
                 distance_m: float, strict: bool, signals: dict[str, float] | None = None,
                 smoothing_rad_s: float | None = None, dt_s: float = 0.004) -> None:
        self.sensor_name, self.lateral, self.gain, self.read = sensor_name, lateral, gain, read
        #: the correction as the motion layer hands it to the servo (motion.path_offset): a step, or on elastic gears
        #: a smooth trajectory lagging c; the laser sees the TCP where that, not c, has put it
        self.applied = PathOffset(1, smoothing_rad_s)
        self.dt_s = dt_s
        self.signals = signals                         #: the process record's signals: seam_error_m each cycle
        self.errors: list[float] = []                  #: the laser's lateral error each cycle the seam was seen
        self.distance_m, self.strict = distance_m, strict
        self.c = 0.0
        self.found_once = False
        self.missing = 0
        self.lost = False
        self.fault: Exception | None = None            #: a SensorFault met in the motion cycle (the robot stopped)
        self.samples: list[tuple[float, float]] = []   #: (s, the seam's lateral offset from the path)

    def __call__(self, view: MotionView) -> tuple[float, float, float] | None:
        sensors = view.sensors
        try:
            value = sensors[self.sensor_name] if sensors is not None and self.sensor_name in sensors else self.read()
        except SensorFault as fault:  # a lost link: stop on the path, the procedure raises it at the statement
            self.fault = fault
            return None
        if value.found:
            self.found_once, self.missing = True, 0
            seam_m = float(self.applied.q[0]) + value.offset_m
            self.samples.append((view.s, seam_m))
            self.errors.append(value.offset_m)
            if self.signals is not None:
                self.signals["seam_error_m"] = value.offset_m
            self.c += self.gain * (seam_m - self.c)
        else:
            self.missing += 1
            if self.strict and ((self.found_once and self.missing >= LOST_CYCLES)
                                or (not self.found_once and view.s * self.distance_m > ACQUIRE_M)):
                self.lost = True
                return None
        self.applied.goal[0] = self.c
        self.applied.rows(SERVO_STEPS, self.dt_s / SERVO_STEPS)  # what the next cycle hands the servo
        v = self.c * self.lateral
        return (float(v[0]), float(v[1]), float(v[2]))


def _laser(robot: Any, name: str | None) -> tuple[str, Any]:
    """The installed laser `name`, or the first installed one, or one installed for RecordSeam (simulated)."""
    from orc_rpl.application.features.sensor_behaviour import sensor_manager

    manager = sensor_manager(robot)
    if name is None:
        name = next((n for n, p in manager.pairs.items() if p.sensor.kind == "LaserDistance"), None)
    if name is None:
        name = "RecordSeamLaser"
        manager.install(name, "LaserDistance", "sim")
    return name, manager.sensor(name)


def _anchor_seam(robot: Any, sensor: Any, start: Any, end: Any) -> None:
    """In simulation, lay the cell's seam along the first path the laser is used along (unless configured)."""
    if sensor.behaviour != "simulated":
        return
    seam = cell_seam(robot.io)
    if not seam.anchored:
        seam.anchor(start, end)


# -- the design stages ----------------------------------------------------------------------------------


def record_seam(path: Any, *, robot: Any, tool: Pose, to_world: Callable[[Pose], Pose] = lambda p: p) -> Any:
    """RecordSeam(path): to the path's start, then slowly along it with standard tracking; the recorded seam."""

    points = path if type(path) is tuple else (path,)
    if len(points) < 2 or any(type(p) is not Pose for p in points):
        raise BehaviourError("RecordSeam needs a PATH of at least two positions along the seam")
    points = tuple(to_world(p) for p in points)
    name, sensor = _laser(robot, None)
    _anchor_seam(robot, sensor, _xyz(points[0]), _xyz(points[-1]))
    was_on = sensor.on
    sensor.command("ON")
    run_to_end(robot, MotionRequest(keyword="RecordSeam", kind="joint", target=points[0], tool=tool),
               MOTION_TIMEOUT_S, "RecordSeam")
    delay_s = loop_delay_cycles(robot, robot.joints()) * robot.dt_s
    smoothing = correction_smoothing_rad_s(robot)
    along: list[float] = []
    offsets: list[float] = []
    travelled = 0.0
    for a, b in zip(points, points[1:]):
        length = math.dist(_xyz(a), _xyz(b))
        tracker = Tracker(name, lateral_direction(_xyz(a), _xyz(b)), STANDARD_GAIN, sensor.read, length, strict=False,
                          smoothing_rad_s=smoothing, dt_s=robot.dt_s)
        run_to_end(robot, MotionRequest(keyword="RecordSeam", kind="linear", target=b, tool=tool,
                                        speed_m_s=RECORD_SPEED_M_S, correction=tracker,
                                        smooth_correction=True), MOTION_TIMEOUT_S, "RecordSeam")
        if tracker.fault is not None:
            raise tracker.fault
        along += [travelled + s * length for s, _ in tracker.samples]
        offsets += [offset for _, offset in tracker.samples]
        travelled += length
    if not was_on:
        sensor.command("OFF")
    if len(offsets) < 10:
        raise BehaviourError("RecordSeam: the laser saw no seam along the path")
    return Record("Seam", (("Position", tuple(Quantity(u, LENGTH) for u in along)),
                           ("Offset", tuple(Quantity(o, LENGTH) for o in offsets)),
                           ("Raggedness", Quantity(_stats(np.array(along), np.array(offsets))[1], LENGTH)),
                           ("LoopDelay", Quantity(delay_s, TIME)),
                           ("Smoothing", Quantity(0.0 if smoothing is None else 1.0 / smoothing, TIME))))


def correction_smoothing_rad_s(robot: Any) -> float | None:
    """The rate (rad/s) at which this robot's motion layer smooths a tracked move's corrections (elastic gears),
    None where a correction is a step."""
    return correction_omega_rad_s(start_averaging_s(robot))


def loop_delay_cycles(robot: Any, q: Any) -> int:
    """The tracking loop's delay on this robot at joint angles q (motion cycles), as Tracking models it: LOOP_DELAY,
    and through elastic gears that take a correction as a step a quarter period of their lowest anti-resonance more
    (the links ring after a step of their reference and lag it by that at the mode's frequency, as many cycles of
    delay would: a loop designed for LOOP_DELAY alone lost the seam within its first 10 mm). Where the motion
    layer smooths corrections (elastic gears under their feed-forward, motion.path_offset) the links follow them
    without that lag, and Tracking models the smoothing itself (the seam's Smoothing)."""
    lowest_rad_s = lowest_anti_resonance_rad_s(robot, q)
    if lowest_rad_s is None or correction_smoothing_rad_s(robot) is not None:
        return LOOP_DELAY
    return LOOP_DELAY + round(0.5 * math.pi / lowest_rad_s / robot.dt_s)


def _xyz(p: Pose) -> tuple[float, float, float]:
    return (p.x, p.y, p.z)


def _seam_arrays(seam: Any) -> tuple[np.ndarray, np.ndarray]:
    try:
        u = np.array([q.value for q in seam.get("Position")])
        o = np.array([q.value for q in seam.get("Offset")])
    except (AttributeError, KeyError):
        raise BehaviourError("expects a seam recorded by RecordSeam") from None
    order = np.argsort(u, kind="stable")
    return u[order], o[order]


def _seam_time_s(seam: Any, field: str) -> float | None:
    """A time field of the seam's record (s), None for a record without it (recorded before it was kept)."""
    try:
        value = seam.get(field)
    except (AttributeError, KeyError):
        return None
    return value.value if type(value) is Quantity else float(value)


def _loop_delay(seam: Any, dt_s: float = 0.004) -> int:
    """The seam's LoopDelay in cycles (LOOP_DELAY for a record without one)."""
    delay_s = _seam_time_s(seam, "LoopDelay")
    return LOOP_DELAY if delay_s is None else max(1, round(delay_s / dt_s))


def _smoothing_rad_s(seam: Any) -> float | None:
    """The seam's Smoothing as the filter's rate (rad/s), None for a record without one or of rigid gears."""
    time_s = _seam_time_s(seam, "Smoothing")
    return 1.0 / time_s if time_s is not None and time_s > 0 else None


def _mean_line(u: np.ndarray, o: np.ndarray) -> np.ndarray:
    """The seam's mean line: its average over MEAN_LINE_M around each sample."""
    c = np.concatenate([[0.0], np.cumsum(o)])
    lo = np.searchsorted(u, u - MEAN_LINE_M / 2)
    hi = np.searchsorted(u, u + MEAN_LINE_M / 2, side="right")
    return (c[hi] - c[lo]) / np.maximum(hi - lo, 1)


def _stats(u: np.ndarray, o: np.ndarray) -> tuple[float, float]:
    """(95th percentile of the mean line's slope, RMS raggedness about it)."""
    if len(u) < 3:
        return 0.0, 0.0
    mean = _mean_line(u, o)
    du = np.diff(u)
    ok = du > 1e-6
    slope = np.abs(np.diff(mean)[ok] / du[ok]) if ok.any() else np.zeros(1)
    return float(np.percentile(slope, 95)), float(np.sqrt(np.mean((o - mean) ** 2)))


def optimal_speed(seam: Any) -> Quantity:
    """OptimalSpeed(seam): see the module's docstring for the rule."""
    u, o = _seam_arrays(seam)
    slope95, ragged = _stats(u, o)
    v = LATERAL_SPEED_M_S / max(slope95, 1e-6) / (1.0 + ragged / RAGGED_REF_M)
    v = min(max(v, V_MIN_M_S), V_MAX_M_S)
    return Quantity(math.floor(v * 1000 + 1e-9) / 1000, VELOCITY)


def simulated_rms(u: np.ndarray, o: np.ndarray, speed: float, gain: float, dt_s: float = 0.004,
                  delay: int = LOOP_DELAY, smoothing_rad_s: float | None = None) -> float:
    """RMS deviation from the seam's mean line of a TCP corrected with `gain`, along the recording at `speed`, the
    laser seeing a correction `delay` cycles after it was made (after the motion layer's smoothing, when
    smoothing_rad_s: the Tracker's loop, which adds the laser's error to the correction as smoothed so far)."""
    mean = _mean_line(u, o)
    grid = np.arange(u[0], u[-1], speed * dt_s)
    seam, target = np.interp(grid, u, o), np.interp(grid, u, mean)
    if smoothing_rad_s is None:
        c = np.zeros(len(grid) + delay)
        for k in range(len(grid)):
            e = seam[k] - c[k]              # the laser sees the TCP where the correction was `delay` cycles ago
            c[k + delay] = c[k + delay - 1] + gain * e if k + delay - 1 >= 0 else 0.0
        return float(np.sqrt(np.mean((target - c[:len(grid)]) ** 2)))
    applied = PathOffset(1, smoothing_rad_s)
    tcp = np.zeros(len(grid) + delay)      # tcp[k + delay]: the smoothed correction made after cycle k's reading
    correction = 0.0
    for k in range(len(grid)):
        seen = float(applied.q[0]) + seam[k] - tcp[k]
        correction += gain * (seen - correction)
        applied.goal[0] = correction
        applied.rows(SERVO_STEPS, dt_s / SERVO_STEPS)
        tcp[k + delay] = applied.q[0]
    return float(np.sqrt(np.mean((target - tcp[:len(grid)]) ** 2)))


def tracking(seam: Any, speed: Any) -> Any:
    """Tracking(seam, speed): the low-pass gain of the correction for this seam at this speed."""

    u, o = _seam_arrays(seam)
    v = speed.value if type(speed) is Quantity else float(speed)
    if not v > 0:
        raise BehaviourError("Tracking needs a speed > 0")
    gains = np.geomspace(0.005, 0.5, 25)
    delay, smoothing = _loop_delay(seam), _smoothing_rad_s(seam)
    errors = [simulated_rms(u, o, v, float(g), delay=delay, smoothing_rad_s=smoothing) for g in gains]
    best = int(np.argmin(errors))
    g = float(gains[best])
    return Record("Tracking", (("Gain", g), ("TimeConstant", Quantity(0.004 / g, TIME)), ("Speed", Quantity(v, VELOCITY)),
                               ("ExpectedError", Quantity(errors[best], LENGTH))))


# -- TRACKMOVE --------------------------------------------------------------------------------------


def trackmove(call: MotionCall) -> Iterator[Any]:
    """TRACKMOVE tool TO target WITH SENSOR = laser WITH TRACKING = params: a straight line corrected by the laser."""
    robot = call.robot
    if robot is None:
        raise BehaviourError("needs a robot")
    installed = call.attributes.get("SENSOR")
    laser = getattr(installed, "behaviour", None)
    if laser is None or not hasattr(laser, "pair"):
        raise BehaviourError("WITH SENSOR = needs an installed LaserDistance")
    params = call.attributes.get("TRACKING")
    if type(params) in (int, float):  # a gain set by hand (a sweep comparing gains with the tuned one)
        gain = float(params)
        if not 0.0 < gain <= 1.0:
            raise BehaviourError(f"WITH TRACKING = {params}: a gain by hand lies in (0, 1] (the correction's share per cycle)")
    else:
        try:
            gain = float(params.get("Gain")) if params is not None else STANDARD_GAIN
        except (AttributeError, KeyError, TypeError, ValueError):
            raise BehaviourError("WITH TRACKING = needs the parameters made by Tracking(seam, speed), or a gain "
                                 "in (0, 1]") from None
    if call.target is None or type(call.target) is Joints or call.path is not None:
        raise BehaviourError("needs a TO position (a straight line along the seam)")
    attributes = {k: v for k, v in call.attributes.items() if k not in ("SENSOR", "TRACKING")}
    base = standard_motion(dataclasses.replace(call, keyword="LMOVE", attributes=attributes))
    start = robot.tcp_pose(call.tool)
    end = base.target
    sensor = laser.sensor
    _anchor_seam(robot, sensor, _xyz(start), _xyz(end))
    if not sensor.on:
        raise BehaviourError(f"the laser {laser.name} is off ({laser.name}.On switches it on)")
    record = process_log(robot)
    tracker = Tracker(laser.name, lateral_direction(_xyz(start), _xyz(end)), gain, sensor.read,
                      math.dist(_xyz(start), _xyz(end)), strict=True, signals=record.signals,
                      smoothing_rad_s=correction_smoothing_rad_s(robot), dt_s=robot.dt_s)
    # whole_averaging: the Tracker's smoothing is the whole periods', and a gentle line's short windows leave
    # its start ringing into the seam (docs/motion.md, "Averaging on elastic gears")
    request = dataclasses.replace(base, keyword=call.keyword, kind="linear", zone_m=0.0, correction=tracker,
                                  smooth_correction=True, whole_averaging=True)
    ticket = yield request
    while not ticket.done:
        yield None
    record.signals["seam_error_m"] = math.nan
    errors = np.abs(np.array(tracker.errors)) if tracker.errors else np.zeros(1)
    record.seams.append(SeamRecord(math.dist(_xyz(start), _xyz(robot.tcp_pose(call.tool))),
                                   float(np.sqrt(np.mean(errors ** 2))), float(errors.max()), gain))
    if ticket.outcome == "fault":
        raise ticket.error if ticket.error is not None else BehaviourError("the motion failed")
    if tracker.fault is not None:
        raise record.fault(tracker.fault, robot.time_s())
    if tracker.lost:
        where = f"{100 * tracker.samples[-1][0]:.0f} %" if tracker.samples else "the start"
        raise record.fault(SeamLost(f"{laser.name} lost the seam at {where} of the path; the robot stopped on its path"),
                           robot.time_s())


def register_behaviour(registry: Any) -> None:
    """Fill the behaviour slots of ArcWelder, TRACKMOVE, RecordSeam, OptimalSpeed and Tracking."""
    kind = registry.install_kinds.get("ArcWelder")
    if kind is not None and kind.factory is None:
        registry.install_kinds["ArcWelder"] = dataclasses.replace(kind, factory=ArcWelder)
    spec = registry.motions.get("TRACKMOVE")
    if spec is not None and spec.execute is None:
        registry.motions["TRACKMOVE"] = dataclasses.replace(spec, execute=trackmove)
    for name, implementation in (("RecordSeam", record_seam), ("OptimalSpeed", optimal_speed), ("Tracking", tracking)):
        function = registry.functions.get(name)
        if function is not None and function.implementation is None:
            registry.functions[name] = dataclasses.replace(function, implementation=implementation)
