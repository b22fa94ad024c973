"""Behaviour of materials handling (thesis 2.5, 4.5): IDENTMOVE with IDENT(proc, parts).

    IDENTMOVE gripper TO DropPositions[Id] VIA TopPos WITH Id = IDENT(proc, parts)

The motion toward the via point starts at once with an action that records torques, q and q-dot for the
first 0.2 s (on elastic gears 0.2 s plus the time the move's start is averaged over: `identify_window`); it
takes at least the recording plus LEAD_S, so a near via point slows the approach just enough for the
identification to end before it (and the blend radius is at most half the way to it). From that recording
the payload is estimated with the robot model (`payload_estimation`: windows without acceleration switches,
friction and offsets per joint, a standard deviation); the user's FUNC `proc` gets the recording
(`recording.payload`, `recording.payload_sigma`, `recording.Torque[j]` the samples of joint j,
`recording.Time`) and returns one of `parts`. The answer is trusted only when `proc` gives the same part from
3 standard deviations below the estimate to 3 above; otherwise IdentUncertain (catchable) is raised and the
robot stops at the via point. `Id` is bound to the answer, the target expression is evaluated then, and the
final motion is sent while the robot still moves toward the via point, so it blends through it.

The tare. The controller's model of the arm is not the arm: a dress pack it does not know, friction that is
twice its nominal value on a cold gearbox, link masses a few percent off. Along one path these errors are the
same lift after lift, but they read as kilograms (the realistic IRB 2400 reads an empty gripper as 11 to
21 kg, depending on the via point and the speed: docs/applications.md, "The tare"). An IDENTMOVE made while every Gripper is open holds
nothing by construction: it is the path's tare, its estimate is kept per path (start, via point, speed, tool)
and the user's FUNC is given 0 kg. Later IDENTMOVEs along the same path take the tare's torques off theirs,
window by window (payload_estimation.estimate with `tare`), and the friction change the controller estimates
since the tare (motion.gear_friction: a cold arm's gearboxes warm lift after lift). One without a tare trusts the model as it is: on
the realistic plant its estimate is off by the model's error and its spread does not show it (not solved).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from orc_rpl.application.features.gears import gear_period_cycles, start_averaging_s
from orc_rpl.application.features.payload_estimation import SIGMAS, WINDOW, PayloadEstimate, confidence, estimate
from orc_rpl.application.process_log import IdentRecord, process_log
from orc_rpl.application.runtime import BehaviourError, FunctionParam, MotionCall, Sample, attached
from orc_rpl.application.standard_behaviour import standard_motion
from orc_rpl.application.values import Record
from orc_rpl.errors import MotionFault
from orc_rpl.motion.gear_friction import change_since
from orc_rpl.syntax.units import MASS, TIME, TORQUE, Quantity
from orc_rpl.world.pose import Pose

#: How long torques are recorded after the start of the motion (thesis 2.5: "0.2 s of torques").
RECORD_S = 0.2
#: The motion toward the via point takes at least RECORD_S plus this: time to classify and send the final
#: motion before the blend toward it begins.
LEAD_S = 0.1
#: Paths whose start and via point lie within this (m) share a tare.
TARE_MATCH_M = 0.002
#: The motion toward the via point blends into the final one within this radius (unless ZONE is larger),
#: at most half the way from the start to the via point.
VIA_ZONE_M = 0.1


class IdentUncertain(MotionFault):
    """IDENTMOVE could not tell the part: the user's classification changes within the estimate's spread."""

    rpl_name = "IdentUncertain"


@dataclass(frozen=True, slots=True)
class Identification:
    """`IDENT(proc, parts)`: what IDENTMOVE runs on the recording (the user's FUNC and the possible results)."""

    proc: Any                 #: the program's FUNC of one parameter (a Routine value)
    parts: tuple[Any, ...]


def ident(proc: Any, parts: Any) -> Identification:
    """IDENT(proc, parts): only meaningful as an IDENTMOVE output binding (`WITH Id = IDENT(proc, parts)`)."""
    if getattr(proc, "kind", None) != "FUNC" or len(getattr(proc, "params", ())) != 1:
        raise BehaviourError("IDENT's first argument must be a FUNC of one parameter (the recording)")
    if type(parts) is not tuple or not parts:
        raise BehaviourError("IDENT's second argument must be a non-empty list of the possible parts")
    return Identification(proc, parts)


def identify_window(robot: Any, q: Any) -> tuple[float, int]:
    """(how long IDENTMOVE records, s; samples per window of the estimate) for a lift from joint angles q: RECORD_S
    and payload_estimation.WINDOW on rigid gears. On elastic gears the motion layer averages a move's start from
    rest over the gears' periods (start_averaging_s, 0.295 s on the IRB 2400), so the recording is that much
    longer (in the first 0.2 s the arm reached 0.36 rad/s where rigid gears reach 1.2), and a window is one period
    of the gears' lowest anti-resonance at q, over which their swing averages out (28 cycles at the pick)."""
    return RECORD_S + start_averaging_s(robot), max(WINDOW, gear_period_cycles(robot, q))


def estimate_payload(samples: list[Sample], inverse_dynamics: Any) -> float:
    """The payload (kg, at least 0) from recorded torques (payload_estimation.estimate)."""
    return max(0.0, estimate(samples, inverse_dynamics).mass_kg)


def recording_value(samples: list[Sample], payload_kg: float, sigma_kg: float = 0.0) -> Any:
    """The recording as the user's FUNC sees it: payload, payload_sigma, Torque[j] (samples of joint j), Time."""

    joints = len(samples[0].torque) if samples else 0
    torque = tuple(tuple(Quantity(s.torque[j], TORQUE) for s in samples) for j in range(joints))
    t0 = samples[0].time_s if samples else 0.0
    return Record("Recording", (("payload", Quantity(payload_kg, MASS)), ("payload_sigma", Quantity(sigma_kg, MASS)),
                                ("Torque", torque),
                                ("Time", tuple(Quantity(s.time_s - t0, TIME) for s in samples))))


def identmove(call: MotionCall) -> Iterator[Any]:
    """IDENTMOVE tool TO target(Id) VIA point WITH Id = IDENT(proc, parts): identify while moving, then go on."""
    robot = call.robot
    if robot is None or call.resolve_target is None or call.call_function is None:
        raise BehaviourError("needs a TO target, a robot and the program's functions")
    if len(call.via) != 1:
        raise BehaviourError("needs exactly one VIA point: the identification is done before it is passed")
    outputs = {name: value for name, value in call.attributes.items()
               if callable(value) and not isinstance(value, FunctionParam)}
    if len(outputs) != 1:
        raise BehaviourError("needs one output binding, WITH Id = IDENT(proc, parts)")
    (name, thunk), = outputs.items()
    identification = thunk()
    if not isinstance(identification, Identification):
        raise BehaviourError(f"{name} must be bound to IDENT(proc, parts)")
    attributes = {k: v for k, v in call.attributes.items() if k not in outputs}
    to_via = standard_motion(dataclasses.replace(call, keyword="MOVE", target=call.via[0], via=(), attributes=attributes))
    zone = max(to_via.zone_m, VIA_ZONE_M)
    here, via = robot.tcp_pose(call.tool), call.via[0]
    if type(via) is Pose:  # blending must not begin before the final motion is known
        zone = min(zone, 0.5 * math.dist((here.x, here.y, here.z), (via.x, via.y, via.z)))
    record_s, window = identify_window(robot, robot.joints())
    # whole_averaging: a lift averaged over less than the gears' whole periods leaves its start's step or its
    # switch to braking inside the recording (the abstentions double on elastic gears: docs/motion.md)
    to_via = dataclasses.replace(to_via, keyword=call.keyword, zone_m=zone, until=None, record_s=record_s,
                                 time_s=max(to_via.time_s or 0.0, record_s + LEAD_S), whole_averaging=True)
    ticket = yield to_via
    # the first sample is one cycle into the motion, the last RECORD_S into it
    while not ticket.done and (not ticket.recording
                               or robot.time_s() < ticket.recording[0].time_s + record_s - robot.dt_s - 1e-9):
        yield None
    if ticket.outcome == "fault":
        raise ticket.error if ticket.error is not None else BehaviourError("the motion toward the via point failed")
    tares = attached(robot, "ident_tares", list)
    path = _path_key(here, via, call.tool, to_via)
    grippers = getattr(robot, "grippers_closed", None)
    taring = bool(grippers) and not any(grippers.values())
    friction = getattr(robot, "friction_state", lambda: None)()  # the controller's friction warm-up estimate
    if taring:  # nothing is held: this lift is the path's tare
        tares[:] = [(k, r, f) for k, r, f in tares if not _same_path(k, path)] + [(path, list(ticket.recording), friction)]
        found = PayloadEstimate(0.0, 0.0, 0)
    else:
        tare, then = next(((r, f) for k, r, f in reversed(tares) if _same_path(k, path)), (None, None))
        change = None if then is None or friction is None else change_since(then, friction)
        found = estimate(ticket.recording, robot.inverse_dynamics, tare, change, window)
    payload_kg = max(0.0, found.mass_kg)
    record = process_log(robot)
    record.signals["payload_kg"] = payload_kg

    def answer_of(mass_kg: float) -> Any:
        return call.call_function(identification.proc, [recording_value(ticket.recording, mass_kg, found.sigma_kg)])
    result, trust, trusted = ((answer_of(0.0), 1.0, True) if taring
                              else confidence(answer_of, found.mass_kg, found.sigma_kg))
    if result not in identification.parts:
        raise BehaviourError(f"{identification.proc.name} gave {result!r}, which is not one of the parts given to IDENT")
    if not trusted:
        record.identifications.append(IdentRecord(payload_kg, found.sigma_kg, trust, ""))
        low, high = (answer_of(max(0.0, found.mass_kg + k * found.sigma_kg)) for k in (-SIGMAS, SIGMAS))
        while not ticket.done:  # no target: the robot stops at the via point
            yield None
        raise record.fault(IdentUncertain(
            f"{identification.proc.name} cannot tell the part: payload {payload_kg:.3f} kg +- {found.sigma_kg:.3f} kg "
            f"gives {_name(result)}, but {_name(low)} at -{SIGMAS:g} sigma and {_name(high)} at +{SIGMAS:g} sigma "
            f"(confidence {100 * trust:.1f} %); the robot stopped at the via point"), robot.time_s())
    record.identifications.append(IdentRecord(payload_kg, found.sigma_kg, trust,
                                              _name(result) + (" (tare)" if taring else "")))
    target = call.resolve_target({name: result})
    final = standard_motion(dataclasses.replace(call, keyword="MOVE", target=target, via=(), attributes=attributes))
    final = dataclasses.replace(final, keyword=call.keyword, zone_m=0.0, until=None,
                                load_kg=max(final.load_kg, payload_kg))
    last = yield final
    while not last.done:
        yield None
    for t in (ticket, last):
        if t.outcome == "fault":
            raise t.error if t.error is not None else BehaviourError("the motion failed")


def _path_key(start: Pose, via: Any, tool: Pose, request: Any) -> tuple[Any, ...]:
    """What makes two lifts the same path for a tare: start and via positions, tool, speed."""
    point = (via.x, via.y, via.z) if type(via) is Pose else tuple(getattr(via, "values", ()))
    return ((start.x, start.y, start.z), point, (tool.x, tool.y, tool.z),
            request.speed_m_s, request.speed_fraction, request.time_s)


def _same_path(a: tuple[Any, ...], b: tuple[Any, ...]) -> bool:
    return (math.dist(a[0], b[0]) <= TARE_MATCH_M and len(a[1]) == len(b[1]) and math.dist(a[1], b[1]) <= TARE_MATCH_M
            and math.dist(a[2], b[2]) <= 1e-6 and a[3:] == b[3:])


def _name(value: Any) -> str:
    """An ENUM value's name (or the value), for messages and the process record."""
    return str(getattr(value, "name", value))


def register_behaviour(registry: Any) -> None:
    """Fill the behaviour slots of IDENTMOVE and IDENT."""
    spec = registry.motions.get("IDENTMOVE")
    if spec is not None and spec.execute is None:
        registry.motions["IDENTMOVE"] = dataclasses.replace(spec, execute=identmove)
    function = registry.functions.get("IDENT")
    if function is not None and function.implementation is None:
        registry.functions["IDENT"] = dataclasses.replace(function, implementation=ident)
