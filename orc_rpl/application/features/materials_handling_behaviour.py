"""Behaviour of materials handling (thesis 2.5, 4.5): IDENTMOVE with IDENT(proc, parts).

    IDENTMOVE gripper TO DropPositions[Id] VIA TopPos WITH Id = IDENT(proc, parts)

The motion toward the via point starts at once with an action that records torques, q and q-dot for the
first 0.2 s. From that recording the payload is estimated with the robot model (inverse dynamics with and
without a unit load at the flange, least squares over every joint and sample); the user's FUNC `proc` gets
the recording (`recording.payload`, `recording.Torque[j]` the samples of joint j, `recording.Time`) and
returns one of `parts`. `Id` is bound to it, the target expression is evaluated then, and the final motion
is sent while the robot still moves toward the via point, so it blends through it. If the identification
comes late, the motion toward the via point has already slowed down and waits there.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from orc_rpl.application.runtime import BehaviourError, FunctionParam, MotionCall, Sample
from orc_rpl.application.standard_behaviour import standard_motion
from orc_rpl.application.values import Record
from orc_rpl.syntax.units import MASS, TIME, TORQUE, Quantity

#: How long torques are recorded after the start of the motion (thesis 2.5: "0.2 s of torques").
RECORD_S = 0.2
#: Samples this close to the start are left out of the estimate (the servo's transient as the motion starts).
SKIP_S = 0.04
#: The motion toward the via point blends into the final one within this radius (unless ZONE is larger).
VIA_ZONE_M = 0.1


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


def estimate_payload(samples: list[Sample], inverse_dynamics: Any) -> float:
    """Least-squares payload (kg) from recorded torques: tau = tau_0(q, qd, qdd) + m * (tau_1 - tau_0)."""
    if not samples:
        return 0.0
    numerator = denominator = 0.0
    for i, sample in enumerate(samples):
        if sample.time_s - samples[0].time_s < SKIP_S - 1e-9:
            continue  # the servo's torque lags the jerk-limited start: a large, load-independent residual
        if i == 0 or sample.time_s <= samples[i - 1].time_s:
            qdd = tuple(0.0 for _ in sample.q)
        else:
            dt = sample.time_s - samples[i - 1].time_s
            qdd = tuple((a - b) / dt for a, b in zip(sample.qd, samples[i - 1].qd))
        tau0 = inverse_dynamics(sample.q, sample.qd, qdd, 0.0)
        tau1 = inverse_dynamics(sample.q, sample.qd, qdd, 1.0)
        for measured, t0, t1 in zip(sample.torque, tau0, tau1):
            d = t1 - t0
            numerator += d * (measured - t0)
            denominator += d * d
    return max(0.0, numerator / denominator) if denominator > 0 else 0.0


def recording_value(samples: list[Sample], payload_kg: float) -> Any:
    """The recording as the user's FUNC sees it: payload, Torque[j] (samples of joint j), Time."""

    joints = len(samples[0].torque) if samples else 0
    torque = tuple(tuple(Quantity(s.torque[j], TORQUE) for s in samples) for j in range(joints))
    t0 = samples[0].time_s if samples else 0.0
    return Record("Recording", (("payload", Quantity(payload_kg, MASS)), ("Torque", torque),
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
    to_via = dataclasses.replace(to_via, keyword=call.keyword, zone_m=max(to_via.zone_m, VIA_ZONE_M), until=None,
                                 record_s=RECORD_S)
    ticket = yield to_via
    # the first sample is one cycle into the motion, the last RECORD_S into it
    while not ticket.done and (not ticket.recording
                               or robot.time_s() < ticket.recording[0].time_s + RECORD_S - robot.dt_s - 1e-9):
        yield None
    if ticket.outcome == "fault":
        raise ticket.error if ticket.error is not None else BehaviourError("the motion toward the via point failed")
    payload_kg = estimate_payload(ticket.recording, robot.inverse_dynamics)
    result = call.call_function(identification.proc, [recording_value(ticket.recording, payload_kg)])
    if result not in identification.parts:
        raise BehaviourError(f"{identification.proc.name} gave {result!r}, which is not one of the parts given to IDENT")
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


def register_behaviour(registry: Any) -> None:
    """Fill the behaviour slots of IDENTMOVE and IDENT."""
    spec = registry.motions.get("IDENTMOVE")
    if spec is not None and spec.execute is None:
        registry.motions["IDENTMOVE"] = dataclasses.replace(spec, execute=identmove)
    function = registry.functions.get("IDENT")
    if function is not None and function.implementation is None:
        registry.functions["IDENT"] = dataclasses.replace(function, implementation=ident)
