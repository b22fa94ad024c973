"""Behaviour of assembly (thesis 2.4, 4.5): CALIBRATE, the dynamic calibration (servo auto-tuning) at a location.

    Tuning = CALIBRATE(ShakyPath)
        MOVE along the short path and back, twice, at the current payload; a recording action in the
        motion cycle gives q, q-dot and the joint torques;
        residual = torque - the controller's model (inverse dynamics at the measured motion);
        per joint, least squares: residual = dJ qdd + b qd + c  (inertia, friction, weight the model lacks);
        gains: the velocity loop scaled by the identified inertia (its bandwidth becomes what it was
        designed for) and raised by BOOST where the identification holds; feed-forward corrections
        dJ, b, c.

The tuning is used by `MOVE ... WITH TUNING = t` for that motion only (the motion layer hands it to the
servo at the start of the motion and restores the default gains when it is done).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from orc_rpl.application.process_log import TuningRecord, process_log
from orc_rpl.application.runtime import BehaviourError, MotionRequest, RobotInterface, Sample, run_to_end
from orc_rpl.servo.control import ServoGains, ServoTuning
from orc_rpl.world.pose import Joints, Pose

#: Excitation: the path and back, this many times.
REPETITIONS = 2
#: Bandwidths are raised by this factor where the identification holds: the default gains keep a margin
#: for the payloads they do not know (robust tuning fixed for the robot, thesis 2.4), a tuning need not.
BOOST = 1.5
#: A joint that accelerates less than this (rms, rad/s^2) during the excitation: only its constant
#: torque (c) is identified, not its inertia and friction.
MIN_EXCITATION_RAD_S2 = 0.5
#: The identified inertia is trusted between these multiples of the model's.
INERTIA_RATIO_RANGE = (0.67, 1.5)
#: Give up when one excitation motion takes longer than this (s of controller time).
MOTION_TIMEOUT_S = 30.0


def calibrate(path: Any, *, robot: RobotInterface, tool: Pose, to_world: Callable[[Pose], Pose] = lambda p: p,
              load_kg: float = 0.0, gains: ServoGains = ServoGains()) -> ServoTuning:
    """CALIBRATE(path): excite the arm along `path` (a PATH or one position) and back; identify; tune."""
    points = path if type(path) is tuple else (path,)
    if not points or any(type(p) not in (Pose, Joints) for p in points):
        raise BehaviourError("CALIBRATE needs a PATH or a position near the current location")
    points = tuple(to_world(p) if type(p) is Pose else p for p in points)
    start = Joints(tuple(robot.joints()))
    recordings: list[list[Sample]] = []
    for _ in range(REPETITIONS):
        for target, via in ((points[-1], points[:-1]), (start, tuple(reversed(points[:-1])))):
            request = MotionRequest(keyword="CALIBRATE", kind="joint", target=target, via=via, tool=tool,
                                    load_kg=load_kg, record_s=MOTION_TIMEOUT_S)
            recordings.append(_move(robot, request))
    model = getattr(robot, "inverse_dynamics", None)
    n = len(start.values)
    if model is None or sum(len(r) for r in recordings) < 10:  # no model or no motion: the default tuning
        tuning = _tuning(gains, np.ones(n), np.ones(n), np.zeros(n), np.zeros(n), np.zeros(n), "no data")
    else:
        tuning = identify(recordings, model, start.values, load_kg, robot.dt_s, gains)
    process_log(robot).tunings.append(TuningRecord({
        "samples": sum(len(r) for r in recordings), "position_gain_1_s": list(tuning.position_gain_1_s),
        "velocity_bw_rad_s": list(tuning.velocity_bw_rad_s), "d_inertia_kg_m2": list(tuning.d_inertia_kg_m2),
        "d_viscous_nm_s": list(tuning.d_viscous_nm_s), "d_offset_nm": list(tuning.d_offset_nm), "label": tuning.label}))
    return tuning


def _move(robot: RobotInterface, request: MotionRequest) -> list[Sample]:
    """Run one excitation motion to its end; the motion layer's recording action gives q, qd, torque each cycle."""
    return list(run_to_end(robot, request, MOTION_TIMEOUT_S, "CALIBRATE").recording)


def identify(recordings: list[list[Sample]], model: Callable[..., Any], q0: tuple[float, ...], load_kg: float,
             dt_s: float, gains: ServoGains = ServoGains()) -> ServoTuning:
    """Least squares per joint on the torque the model does not explain; the tuning that follows."""
    parts = []
    for samples in recordings:
        if len(samples) < 3:
            continue
        q = np.array([s.q for s in samples])
        qd = np.array([s.qd for s in samples])
        tau = np.array([s.torque for s in samples])
        qdd = np.gradient(qd, dt_s, axis=0)  # the samples are one motion cycle apart
        parts.append((q, qd, qdd, tau))
    q, qd, qdd, tau = (np.vstack([p[i] for p in parts]) for i in range(4))
    predicted = np.array([model(tuple(a), tuple(b), tuple(c), load_kg) for a, b, c in zip(q, qd, qdd)])
    residual = tau - predicted
    n = q.shape[1]
    zero = (0.0,) * n
    at_rest = np.array(model(tuple(q0), zero, zero, load_kg))
    m_model = np.array([model(tuple(q0), zero, tuple(1.0 if i == j else 0.0 for i in range(n)), load_kg)[j]
                        - at_rest[j] for j in range(n)])
    d_inertia, d_viscous, d_offset = np.zeros(n), np.zeros(n), np.zeros(n)
    excited = np.sqrt(np.mean(qdd ** 2, axis=0)) >= MIN_EXCITATION_RAD_S2
    for j in range(n):
        if excited[j]:
            regressors = np.column_stack([qdd[:, j], qd[:, j], np.ones(len(q))])
            (d_inertia[j], d_viscous[j], d_offset[j]), *_ = np.linalg.lstsq(regressors, residual[:, j], rcond=None)
        else:
            d_offset[j] = float(np.mean(residual[:, j]))
    low, high = INERTIA_RATIO_RANGE
    raw = (m_model + d_inertia) / np.maximum(m_model, 1e-9)
    trusted = excited & (raw >= low) & (raw <= high)
    # an inertia outside the trusted range is an identification gone wrong (or a payload far beyond the
    # arm's rating): that joint keeps the model's inertia and the robust default bandwidth
    ratio = np.where(trusted, raw, 1.0)
    d_inertia = np.where(trusted, d_inertia, 0.0)
    d_viscous = np.where(trusted, d_viscous, 0.0)
    boost = np.where(excited & ~trusted, 1.0, BOOST)
    note = "" if np.all(trusted | ~excited) else "inertia not trusted on joint " + ", ".join(str(j + 1) for j in np.nonzero(excited & ~trusted)[0])
    return _tuning(gains, ratio, boost, d_inertia, d_viscous, d_offset, note)


def _tuning(gains: ServoGains, ratio: np.ndarray, boost: np.ndarray, d_inertia: np.ndarray,
            d_viscous: np.ndarray, d_offset: np.ndarray, note: str) -> ServoTuning:
    kp = gains.position_gain_1_s * boost
    bw = gains.velocity_bw_rad_s * ratio * boost
    ibw = np.full(len(ratio), gains.integral_bw_rad_s)
    label = (f"tuning(bandwidth = {_numbers(gains.velocity_bw_rad_s * boost, 0)} rad/s, "
             f"inertia = {_numbers(ratio, 3)} x model, offset = {_numbers(d_offset, 1)} N m"
             + (f", {note}" if note else "") + ")")
    return ServoTuning(tuple(kp.tolist()), tuple(bw.tolist()), tuple(ibw.tolist()), tuple(d_inertia.tolist()),
                       tuple(d_viscous.tolist()), tuple(d_offset.tolist()), label)


def _numbers(values: np.ndarray, digits: int) -> str:
    """`[1, 2.5, 0]`: rounded, without trailing zeros."""
    def one(v: float) -> str:
        text = f"{round(float(v), digits) + 0.0:.{digits}f}"
        return text.rstrip("0").rstrip(".") if "." in text else text
    return "[" + ", ".join(one(v) for v in values) + "]"
