"""Behaviour of deburring (thesis 2.1, 4.5): GRINDMOVE with force control normal to the path, GrindingPars.

    GrindMove(BurrPath, ...)
        do {
            Move(BurrPath, GrindPars, Act);          -- Act: CatchBulge records the position error along s
            Wait(Act->MoveSignal);
            if (event == BULGE) {
                s0s1h = ComputeBulge(ActResult);
                s2 = StopMove();
                GrindDownBulge(s0s1h, s2);           -- back and forth over [s0, s1]
                BurrPath = PathLeft(BurrPath, s2);
            }
        } while (event == BULGE);

An installed Grinder without a force flange presses with the arm itself and reads the force from its motor
torques (deburring_arm: the thesis' way, no extra sensor). With a flange (or a plain TOOL), as follows.
The grinder sits on a compliant flange with a stroke u along the tool's z axis (normal to the path): the
analog output AnalogOut[8] commands the stroke (m, positive toward the part), the analog input AnalogIn[8] is the
measured normal force (N). The force loop (deburring_flange.ForceLoop) runs every motion cycle (dt = 4 ms), an
integral admittance law

    u <- clip(u + K dt (F_cmd(s) - F_measured), -10 mm, +10 mm),   K = 2.5e-3 m/(N s)

With a contact stiffness k the loop gain is g = K dt k (0.5 at the cell's 50 N/mm): the force error shrinks
by (1 - g) each cycle, stable for 0 < g < 2, so the contact may be up to four times stiffer than assumed.

CatchBulge: each cycle the tool tip's position error normal to the nominal path, e = (TCP - P(s)) . n - u, is
recorded against s (n: the path's outward normal, minus the tool's z axis). Under force control the tip rides
on the edge, so e follows the edge's profile (less the constant penetration F / k). A bulge is where e rises
more than tolerance / 2 above the median of the last 25 samples outside bulges; it is caught when e has come
down again and its top was above the tolerance. The motion is stopped (s2), the bulge [s0, s1] is ground
back and forth, 10 mm beyond each side, until a pass measures it within the tolerance or `max_passes` passes
are done, and the path is resumed from where the robot is (PathLeft). A bulge still above the tolerance after
`max_passes` raises BurrLeft at the end of the path (the rest of the path is ground first). The force loop
watches itself: an error that oscillates about the command with an RMS above half of it over 100 ms (a contact
stiffer than the loop's gain allows) stops the robot, retracts the stroke and raises ProcessFault.
"""

from __future__ import annotations

import dataclasses
import math
import statistics
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from orc_rpl.application.features.deburring_arm import ArmForceLoop
from orc_rpl.application.features.deburring_flange import FORCE_IN, STROKE_OUT, ForceLoop, ForceWatch
from orc_rpl.application.process_log import BulgeRecord, ProcessFault, ProcessLog, process_log
from orc_rpl.application.runtime import BehaviourError, FunctionParam, MotionCall, MotionRequest
from orc_rpl.errors import MotionFault
from orc_rpl.application.standard_behaviour import standard_motion
from orc_rpl.application.values import Record
from orc_rpl.syntax.units import DIMENSIONLESS, FORCE, LENGTH, Quantity
from orc_rpl.world.pose import Pose

#: Default grinding force (N), tolerance (m) and extra passes.
DEFAULT_FORCE_N = 30.0
DEFAULT_TOLERANCE_M = 0.0002
DEFAULT_MAX_PASSES = 4
#: Samples of the baseline (outside bulges), and how far beyond a bulge each grinding pass goes (m).
BASELINE_SAMPLES = 25
PASS_MARGIN_M = 0.01
#: The contact has settled when the force first comes within this fraction of the commanded one.
SETTLED_FRACTION = 0.2
#: The arm's watch reads each cycle's own estimate (an oscillation faster than its average must show), whose
#: noise and model error reach 17 N RMS over 100 ms on the realistic plant: unstable above the command itself.
ARM_UNSTABLE_FRACTION = 1.0
#: The arm's force loop (deburring_arm) was measured stable on the cell up to this contact stiffness (N/m) and
#: oscillating at five times it.
ARM_STIFFNESS_LIMIT_N_M = 1e6


class BurrLeft(MotionFault):
    """GRINDMOVE left a bulge above the tolerance after `max_passes` passes."""

    rpl_name = "BurrLeft"


def grinding_pars(tolerance: Any = None, max_passes: Any = None) -> Any:
    """GrindingPars(tolerance = 0.2mm, max_passes = 4): a record usable as GRINDING / DEBURRING."""

    tol = Quantity(DEFAULT_TOLERANCE_M, LENGTH) if tolerance is None else tolerance
    if not (type(tol) is Quantity and tol.dim == LENGTH and tol.value > 0):
        raise BehaviourError(f"GrindingPars: tolerance must be a length > 0 (e.g. 0.2mm), got {tolerance}")
    passes = DEFAULT_MAX_PASSES if max_passes is None else max_passes
    if type(passes) is Quantity and passes.dim == DIMENSIONLESS:
        passes = passes.value
    if type(passes) not in (int, float) or passes < 0 or passes != int(passes):
        raise BehaviourError(f"GrindingPars: max_passes must be a whole number >= 0, got {max_passes}")
    return Record("GrindingPars", (("tolerance", tol), ("max_passes", int(passes))))


def _pars(value: Any) -> tuple[float, int]:
    if value is None:
        return DEFAULT_TOLERANCE_M, DEFAULT_MAX_PASSES
    if getattr(value, "type_name", None) != "GrindingPars":
        raise BehaviourError(f"GRINDING must be GrindingPars(tolerance, max_passes), got {value!r}")
    return float(value.get("tolerance").value), int(value.get("max_passes"))


def _newtons(value: Any) -> float:
    if type(value) is Quantity and value.dim == FORCE and value.value >= 0:
        return float(value.value)
    if type(value) in (int, float) and value >= 0:
        return float(value)  # the declared default, in N
    raise BehaviourError(f"FORCE must be a force >= 0 (e.g. 30N) or a FUNC of s giving one, got {value}")


@dataclass(slots=True)
class Pass:
    """One traverse over a bulge: its direction and the height measured on it (m)."""

    forward: bool
    measured_m: float


@dataclass(slots=True)
class CaughtBulge:
    """ComputeBulge's result and what grinding it down did."""

    s0: float                 #: path coordinate (0..1) where it starts
    s1: float                 #: and ends
    height_m: float           #: its top above the edge, as caught
    s2: float                 #: where StopMove stopped the robot
    passes: list[Pass] = field(default_factory=list)
    within_tolerance: bool = False


@dataclass(slots=True)
class GrindLog:
    """What a GRINDMOVE did, for tests and figures: the recording, the force loop, the bulges."""

    samples: list[tuple[float, float, float, float, float]] = field(default_factory=list)  #: (t, s, e, F_cmd, F)
    bulges: list[CaughtBulge] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)


class PathGeometry:
    """The nominal path as a polyline of TCP positions: arc length, projection, poses along it."""

    def __init__(self, poses: list[Pose]) -> None:
        self.poses = poses
        self.points = np.array([(p.x, p.y, p.z) for p in poses], dtype=float)
        segments = np.diff(self.points, axis=0)
        self.lengths = np.linalg.norm(segments, axis=1)
        if len(poses) < 2 or np.any(self.lengths < 1e-6):
            raise BehaviourError("needs a path of at least two distinct positions")
        self.starts = np.concatenate(([0.0], np.cumsum(self.lengths)))
        self.length_m = float(self.starts[-1])
        first = poses[0].matrix()
        self.normal = -first[:3, 2]  # the grinder presses along its own z axis: the outward normal is minus it

    def project(self, x: np.ndarray) -> tuple[float, np.ndarray]:
        """(arc length, nominal point) of the path point nearest to x."""
        best_d = math.inf
        best_s, best_p = 0.0, self.points[0]
        for i in range(len(self.lengths)):
            start = self.points[i]
            direction = (self.points[i + 1] - start) / self.lengths[i]
            along = float(np.clip(np.dot(x - start, direction), 0.0, self.lengths[i]))
            p = start + along * direction
            d = float(np.linalg.norm(x - p - np.dot(x - p, self.normal) * self.normal))
            if d < best_d - 1e-12:
                best_d, best_s, best_p = d, float(self.starts[i]) + along, p
        return best_s, best_p

    def pose_at(self, arc_m: float) -> Pose:
        arc = min(max(arc_m, 0.0), self.length_m)
        i = int(min(np.searchsorted(self.starts, arc, side="right") - 1, len(self.lengths) - 1))
        fraction = (arc - self.starts[i]) / self.lengths[i]
        x, y, z = self.points[i] + fraction * (self.points[i + 1] - self.points[i])
        p = self.poses[i] if fraction < 0.5 else self.poses[i + 1]
        return Pose(float(x), float(y), float(z), p.a, p.b, p.c)

    def vertices_after(self, arc_m: float) -> list[Pose]:
        """The path's points beyond arc length `arc_m` (the last one always)."""
        later = [p for p, s in zip(self.poses[1:-1], self.starts[1:-1]) if s > arc_m + 1e-4]
        return [*later, self.poses[-1]]


class CatchBulge:
    """The action's detector: position errors e along s, a bulge when e stands above the baseline."""

    def __init__(self, tolerance_m: float, settled: bool = False) -> None:
        self.tolerance_m = tolerance_m
        self.settled = settled
        self.baseline: list[float] = []
        self.inside: list[tuple[float, float]] = []   #: (arc, e) of the bulge being passed
        self.base_at_start = 0.0

    def add(self, arc_m: float, e: float) -> tuple[float, float, float] | None:
        """A sample; (start arc, end arc, height) when a bulge above the tolerance has just been passed."""
        if not self.settled:
            return None
        if len(self.baseline) < 5:
            self.baseline.append(e)
            return None
        base = statistics.median(self.baseline[-BASELINE_SAMPLES:]) if not self.inside else self.base_at_start
        if e - base > self.tolerance_m / 2:
            if not self.inside:
                self.base_at_start = base
            self.inside.append((arc_m, e))
            return None
        if self.inside:
            passed, self.inside = self.inside, []
            height = max(x for _, x in passed) - base
            if height > self.tolerance_m:
                arcs = [a for a, _ in passed]
                return min(arcs), max(arcs), height
        self.baseline.append(e)
        return None


def grindmove(call: MotionCall, log: GrindLog | None = None) -> Iterator[Any]:
    """GRINDMOVE grinder ALONG path (or TO target) WITH FORCE = f WITH GRINDING = GrindingPars(...)."""
    robot = call.robot
    if robot is None:
        raise BehaviourError("needs a robot")
    log = log if log is not None else GrindLog()
    while robot.pending() > 0:  # grinding starts from rest: a blended motion before it ends first
        yield None
    here = robot.tcp_pose(call.tool)
    poses = list(call.path) if call.path is not None else [here, call.target]
    poses += list(call.via) if call.path is not None else []
    if not all(type(p) is Pose for p in poses):
        raise BehaviourError("grinds along poses (a PATH of poses or a pose target), not joint positions")
    geometry = PathGeometry(poses)  # type: ignore[arg-type]
    tolerance_m, max_passes = _pars(call.attributes.get("GRINDING"))
    force_value = call.attributes.get("FORCE")
    if isinstance(force_value, FunctionParam):
        def force(s: float) -> float:
            return _newtons(force_value.fn(min(1.0, max(0.0, s))))
        force(0.0)
    else:
        constant = DEFAULT_FORCE_N if force_value is None else _newtons(force_value)

        def force(s: float) -> float:
            return constant
    attributes = {k: v for k, v in call.attributes.items() if k not in ("FORCE", "GRINDING")}
    base = standard_motion(dataclasses.replace(call, keyword="LMOVE", target=poses[-1], path=None, via=(),
                                               attributes=attributes, until=None))
    base = dataclasses.replace(base, keyword=call.keyword, zone_m=0.0)
    length = geometry.length_m
    normal = geometry.normal

    def arc_here() -> float:
        return geometry.project(_position(robot.tcp_pose(call.tool)))[0]

    loop = _force_loop(call, force, geometry, arc_here)
    record = process_log(robot)

    def press(start_m: float, end_m: float, via: tuple[Pose, ...] = ()) -> Iterator[Any]:
        """Submit the grinding move from arc start_m to end_m (the path's own end at its end); its ticket."""
        target = geometry.pose_at(end_m) if end_m < length - 1e-9 else poses[-1]
        return (yield from loop.pressed_move(base, start_m, end_m, target, via))

    def sample() -> tuple[float, float, float]:
        """One cycle of the force loop and of CatchBulge's recording: (arc length, normal position error, commanded
        force), the user's FORCE evaluated once (in the loop's step)."""
        tcp = robot.tcp_pose(call.tool)
        x = np.array((tcp.x, tcp.y, tcp.z))
        arc, nominal = geometry.project(x)
        e = float(np.dot(x - nominal, normal)) - loop.tip_offset_m()
        command, measured = loop.step(arc / length, arc)
        log.samples.append((robot.time_s(), arc / length, e, command, measured))
        record.signals.update(force_n=measured, force_cmd_n=command, stroke_m=loop.stroke_m, normal_error_m=e)
        why = loop.unstable()
        if why is not None:
            robot.stop()
            loop.retract()
            _quiet(record)
            raise record.fault(ProcessFault(f"{why}; the robot stopped at s = {arc / length:.3f}"), robot.time_s())
        return arc, e, command

    def finish(ticket: Any) -> Iterator[Any]:
        while not ticket.done:
            yield None
            sample()
        if ticket.outcome == "fault":
            loop.retract()
            raise ticket.error if ticket.error is not None else BehaviourError("the motion failed")

    if math.dist((here.x, here.y, here.z), tuple(geometry.points[0])) > 1e-3:  # to the start of the edge, not grinding
        ticket = yield dataclasses.replace(base, target=loop.approach(poses[0]), via=())
        while not ticket.done:
            yield None
        if ticket.outcome == "fault":
            raise ticket.error if ticket.error is not None else BehaviourError("the motion to the path's start failed")
    arc_now = 0.0
    handled: list[tuple[float, float]] = []
    settled = False
    calm = 0  # cycles in a row the force has been within SETTLED_FRACTION of the command
    while True:
        rest = geometry.vertices_after(arc_now)
        ticket = yield from press(arc_now, length, tuple(rest[:-1]))  # Move(BurrPath, Par, Act)
        catch = CatchBulge(tolerance_m, settled)
        caught = None
        while not ticket.done:
            yield None
            arc, e, command = sample()
            near = abs(loop.measured_n() - command) <= SETTLED_FRACTION * command
            calm = calm + 1 if near else 0
            if not catch.settled and calm >= loop.settle_cycles:
                catch.settled = settled = True
            found = catch.add(arc, e)
            if found is not None and caught is None \
                    and not any(found[0] <= b1 and found[1] >= b0 for b0, b1 in handled):
                caught = found
                robot.stop()  # s2 = StopMove()
        yield from finish(ticket)
        if caught is None:
            break
        s0_m, s1_m, height = caught
        arc_now = arc_here()
        bulge = CaughtBulge(s0_m / length, s1_m / length, height, arc_now / length)
        log.bulges.append(bulge)
        handled.append((s0_m - PASS_MARGIN_M, s1_m + PASS_MARGIN_M))
        yield from grind_down(bulge, s0_m, s1_m, max_passes, tolerance_m, geometry, base, sample, finish, press,
                              loop.stays_on_edge)
        left = bulge.passes[-1].measured_m if bulge.passes else height
        record.bulges.append(BulgeRecord(bulge.s0, bulge.s1, height, tuple(p.measured_m for p in bulge.passes),
                                         left, bulge.within_tolerance))
        if not bulge.within_tolerance:
            log.warnings.append(f"a bulge at s = {bulge.s0:.3f}..{bulge.s1:.3f} still measures {1000 * left:.2f} mm "
                                f"after {max_passes} passes (tolerance {1000 * tolerance_m:.2f} mm)")
        arc_now = arc_here()  # BurrPath = PathLeft(BurrPath, s2)
        if arc_now >= length - 1e-4:
            break
    yield from loop.leave(base, poses[-1])
    _quiet(record)
    if log.warnings:
        raise record.fault(BurrLeft("; ".join(log.warnings) + "; more passes (max_passes) or a higher FORCE needed"),
                           robot.time_s())
    message = loop.nothing_ground(settled)
    if message is not None:
        log.warnings.append(message)
        call.warn(message)


def _force_loop(call: MotionCall, force: Callable[[float], float], geometry: PathGeometry,
                arc_here: Callable[[], float]) -> ForceLoop | ArmForceLoop:
    """The force loop GRINDMOVE presses with: a Grinder's force flange (its own wiring, AnalogIn/AnalogOut[8] for a
    plain TOOL), or, for an installed Grinder without one, the arm itself feeling the force in its motor torques."""
    robot = call.robot
    flange = getattr(call.equipment, "force_flange", None)
    if flange is None and hasattr(call.equipment, "force_flange"):
        watch = ForceWatch(robot.dt_s, ARM_STIFFNESS_LIMIT_N_M, ARM_UNSTABLE_FRACTION)
        return ArmForceLoop(robot, force, call.tool, watch, geometry, arc_here)
    return ForceLoop(robot, force, *(flange or (FORCE_IN, STROKE_OUT)))


def _quiet(record: ProcessLog) -> None:
    """No grinding any more: the grinding signals are not defined (NaN in the recording)."""
    record.signals.update(force_n=math.nan, force_cmd_n=math.nan, stroke_m=math.nan, normal_error_m=math.nan)


def grind_down(bulge: CaughtBulge, s0_m: float, s1_m: float, max_passes: int, tolerance_m: float,
               geometry: PathGeometry, base: MotionRequest, sample: Callable[[], tuple[float, float, float]],
               finish: Callable[[Any], Iterator[Any]], press: Callable[[float, float], Iterator[Any]],
               stays_on_edge: bool) -> Iterator[Any]:
    """GrindDownBulge: back and forth over [s0, s1] (10 mm beyond), each pass measuring what is left. `press`
    submits a pass; a loop that `stays_on_edge` starts it where the robot is, the arm's lifts off to its start."""
    low, high = max(0.0, s0_m - PASS_MARGIN_M), min(geometry.length_m, s1_m + PASS_MARGIN_M)
    here = geometry.project(_position_of_last(geometry, bulge))[0]
    forward = here < (low + high) / 2
    if low < here < high and stays_on_edge:  # stopped on the bulge: go to its nearer end first, not grinding it yet
        ticket = yield dataclasses.replace(base, target=geometry.pose_at(low if forward else high), via=())
        yield from finish(ticket)
    for _ in range(max_passes):
        ticket = yield from press(low if forward else high, high if forward else low)
        outside: list[float] = []
        on: list[float] = []
        while not ticket.done:
            yield None
            arc, e, _ = sample()
            (on if s0_m <= arc <= s1_m else outside).append(e)
        yield from finish(ticket)
        reference = statistics.median(outside) if outside else 0.0
        measured = max(on) - reference if on else 0.0
        bulge.passes.append(Pass(forward, measured))
        forward = not forward
        if measured <= tolerance_m:
            bulge.within_tolerance = True
            break


def _position(pose: Pose) -> np.ndarray:
    return np.array((pose.x, pose.y, pose.z))


def _position_of_last(geometry: PathGeometry, bulge: CaughtBulge) -> np.ndarray:
    return _position(geometry.pose_at(bulge.s2 * geometry.length_m))


def register_behaviour(registry: Any) -> None:
    """Fill the behaviour slots of GRINDMOVE and GrindingPars."""
    spec = registry.motions.get("GRINDMOVE")
    if spec is not None and spec.execute is None:
        registry.motions["GRINDMOVE"] = dataclasses.replace(spec, execute=grindmove)
    function = registry.functions.get("GrindingPars")
    if function is not None and function.implementation is None:
        registry.functions["GrindingPars"] = dataclasses.replace(function, implementation=grinding_pars)
