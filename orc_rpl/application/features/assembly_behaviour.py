"""Behaviour of assembly (thesis 2.4, 4.5): CALIBRATE, the dynamic calibration (servo auto-tuning) at a location.

    Tuning = CALIBRATE(ShakyPath)
        MOVE along the short path and back, twice, at the current payload; a recording action in the
        motion cycle gives q, q-dot and the joint torques;
        residual = torque - the controller's model (inverse dynamics at the measured motion);
        per joint, least squares: residual = dJ qdd + b qd + fc tanh(qd / 0.05) + c
            (inertia, friction, weight the model lacks);
        load: the constant torques c as one mass at the flange, fed forward through the model at every pose;
        friction: fc over the servo's nominal Coulomb friction, a factor on the nominal friction it feeds forward;
            on elastic gears also how sharply it turns with the speed (the smoothing of tanh that fits best);
        gains: BOOST times the robot's own, the velocity loop scaled by the identified inertia; a joint with an
        elastic gear whose anti-resonance (at the identified inertia) the boost would cross keeps its own;
        feed-forward corrections dJ, b, c for what the load and the friction do not explain.

The tuning is used by `MOVE ... WITH TUNING = t` for that motion only (the motion layer hands it to the
servo at the start of the motion and restores the default gains when it is done).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from orc_rpl.application.process_log import TuningRecord, process_log
from orc_rpl.application.runtime import BehaviourError, MotionRequest, RobotInterface, Sample, run_to_end
from orc_rpl.servo.control import FRICTION_SMOOTH_RAD_S, ServoGains, ServoTuning
from orc_rpl.servo.two_mass import POSITION_OVER_VELOCITY
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
              load_kg: float = 0.0, gains: ServoGains | None = None) -> ServoTuning:
    """CALIBRATE(path): excite the arm along `path` (a PATH or one position) and back; identify; tune.

    `gains`: the servo's default gains the tuning starts from (None: the robot's own, `servo_gains()`, with its
    per-joint caps and elastic gears; the plain `ServoGains()` on a robot that has none)."""
    points = path if type(path) is tuple else (path,)
    if not points or any(type(p) not in (Pose, Joints) for p in points):
        raise BehaviourError("CALIBRATE needs a PATH or a position near the current location")
    if gains is None:
        own = getattr(robot, "servo_gains", None)
        gains = (own() if own is not None else None) or ServoGains()
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
        kp, bw = gains.per_joint(n)
        tuning = _tuning(gains, kp, bw, np.ones(n), np.zeros(n), np.zeros(n), np.zeros(n), 0.0, "no data")
    else:
        own_friction = getattr(robot, "servo_friction", None)
        friction = own_friction() if own_friction is not None else None
        tuning = identify(recordings, model, start.values, load_kg, robot.dt_s, gains, friction=friction)
    process_log(robot).tunings.append(TuningRecord({
        "samples": sum(len(r) for r in recordings), "position_gain_1_s": list(tuning.position_gain_1_s),
        "velocity_bw_rad_s": list(tuning.velocity_bw_rad_s), "d_inertia_kg_m2": list(tuning.d_inertia_kg_m2),
        "d_viscous_nm_s": list(tuning.d_viscous_nm_s), "d_offset_nm": list(tuning.d_offset_nm),
        "load_kg": tuning.load_kg, "friction_factor": list(tuning.friction_factor), "label": tuning.label}))
    return tuning


def _move(robot: RobotInterface, request: MotionRequest) -> list[Sample]:
    """Run one excitation motion to its end; the motion layer's recording action gives q, qd, torque each cycle."""
    return list(run_to_end(robot, request, MOTION_TIMEOUT_S, "CALIBRATE").recording)


#: The parts of the identified tuning; `identify(..., leave_out=...)` switches parts off (to credit each its effect).
#: load: the weight the model lacks as a mass at the flange, fed forward through the model at every pose;
#: friction: the joints' friction as identified, as a factor on the model's nominal friction (a cold gearbox);
#: placement: bandwidths placed per joint (below an elastic gear's anti-resonance at the identified inertia) instead
#: of the uniform BOOST; inertia: the velocity loop scaled by the identified inertia; feedforward: the dJ, b, c
#: corrections (without load: all of the weight as constant offsets).
PARTS = ("load", "friction", "placement", "inertia", "feedforward")
#: The identified friction factor is trusted between these multiples of the nominal friction.
FRICTION_FACTOR_RANGE = (0.5, 3.0)
#: A joint's Coulomb friction is identified only where it turned faster than this (rad/s, rms) during the
#: excitation: slower, the smoothed sign tanh(qd / FRICTION_SMOOTH_RAD_S) is nearly the speed itself and the fit
#: cannot tell Coulomb from viscous friction (elastic gears' averaged excitation, 0.053 rad/s rms: j1 read 2.3
#: times the cold-start friction the servo already fed forward; rigid gears' 0.2 rad/s read 2.15 to 2.56 times the
#: nominal against the plant's 2.2).
MIN_FRICTION_SPEED_RAD_S = 2.0 * FRICTION_SMOOTH_RAD_S
#: How sharply the friction turns with the speed: the Coulomb term's smoothing speeds (rad/s) the fit tries, the
#: servo's own first; a joint's is the one that leaves the least residual. Identified on the joints that turned
#: faster than MIN_SHARPNESS_SPEED_RAD_S (rms), the tuning takes their median; the state feedback for elastic gears
#: smooths its Coulomb feed-forward over it while the tuning holds (ServoTuning.friction_smooth_rad_s).
FRICTION_SMOOTH_CANDIDATES_RAD_S = (FRICTION_SMOOTH_RAD_S, 0.04, 0.03, 0.025, 0.02, 0.015, 0.01)
MIN_SHARPNESS_SPEED_RAD_S = 0.02


def identify(recordings: list[list[Sample]], model: Callable[..., Any], q0: tuple[float, ...], load_kg: float,
             dt_s: float, gains: ServoGains = ServoGains(), leave_out: frozenset[str] = frozenset(),
             friction: tuple[Any, Any] | None = None) -> ServoTuning:
    """Least squares per joint on the torque the model does not explain; the tuning that follows.

    `model` is the rigid-body model (no friction): the rest includes all of the joints' friction. `friction`: the
    nominal (Coulomb, viscous) friction the servo feeds forward already, None when it feeds none."""
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
    d_inertia, d_viscous, d_offset, coulomb = np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)
    excited = np.sqrt(np.mean(qdd ** 2, axis=0)) >= MIN_EXCITATION_RAD_S2
    with_coulomb = friction is not None and "friction" not in leave_out
    speed_rms = np.sqrt(np.mean(qd ** 2, axis=0))
    # only elastic gears' state feedback reads it (on rigid gears the tuning is as before)
    sharp = [_sharpness(qdd[:, j], qd[:, j], residual[:, j]) for j in range(n) if with_coulomb
             and gains.gear_stiffness_nm_rad and excited[j] and speed_rms[j] >= MIN_SHARPNESS_SPEED_RAD_S]
    for j in range(n):
        if excited[j]:
            columns = [qdd[:, j], qd[:, j], np.ones(len(q))]
            if with_coulomb:  # the Coulomb friction as the servo models it (smoothed sign of the speed)
                columns.append(np.tanh(qd[:, j] / FRICTION_SMOOTH_RAD_S))
            fit, *_ = np.linalg.lstsq(np.column_stack(columns), residual[:, j], rcond=None)
            d_inertia[j], d_viscous[j], d_offset[j] = fit[:3]
            coulomb[j] = fit[3] if with_coulomb else 0.0
        else:
            d_offset[j] = float(np.mean(residual[:, j]))
    factor = np.ones(n)
    if with_coulomb:
        # the friction of the joints the path moved, over the nominal; the others take their median (the gearboxes
        # of a robot started cold warm up together)
        nominal_c = np.asarray(friction[0], dtype=float)  # type: ignore[index]
        fast = speed_rms >= MIN_FRICTION_SPEED_RAD_S
        measured = excited & fast & (nominal_c > 0)
        factor[measured] = coulomb[measured] / nominal_c[measured]
        f_low, f_high = FRICTION_FACTOR_RANGE
        good = measured & (factor >= f_low) & (factor <= f_high)
        factor[~good] = float(np.median(factor[good])) if np.any(good) else 1.0
    if friction is not None:  # the servo feeds forward (nominal) viscous friction already: only the rest
        d_viscous = d_viscous - factor * np.asarray(friction[1], dtype=float)
    m_model = _inertia(model, q0, load_kg)
    low, high = INERTIA_RATIO_RANGE
    raw = (m_model + d_inertia) / np.maximum(m_model, 1e-9)
    trusted = excited & (raw >= low) & (raw <= high)
    # an inertia outside the trusted range is an identification gone wrong (or a payload far beyond the
    # arm's rating): that joint keeps the model's inertia and the robust default bandwidth
    d_inertia = np.where(trusted, d_inertia, 0.0)
    d_viscous = np.where(trusted, d_viscous, 0.0)
    extra_kg = 0.0
    m_tuned = m_model  # the model's inertia as the servo will have it while the tuning holds
    identified_kg_m2 = m_model + d_inertia  # each joint's inertia at q0 as identified (the model's where not trusted)
    if "load" not in leave_out:
        # the constant torques are mostly weight the model lacks (a payload not declared, a dress pack): as a mass
        # at the flange it is fed forward through the model at every pose of the motion, on every joint, with
        # its inertia (the approach moves joints the excitation did not)
        zero = (0.0,) * n
        per_kg = np.array(model(tuple(q0), zero, zero, load_kg + 1.0)) - np.array(model(tuple(q0), zero, zero, load_kg))
        if float(per_kg @ per_kg) > 1e-12:
            extra_kg = max(0.0, float(per_kg @ d_offset) / float(per_kg @ per_kg))
        d_offset = d_offset - extra_kg * per_kg
        m_tuned = _inertia(model, q0, load_kg + extra_kg)
        d_inertia = np.where(trusted, identified_kg_m2 - m_tuned, 0.0)
    inertia_kg_m2 = np.where(trusted, identified_kg_m2, m_tuned)
    ratio = np.where(trusted, inertia_kg_m2 / np.maximum(m_tuned, 1e-9), 1.0) if "inertia" not in leave_out else np.ones(n)
    kp0, bw0 = gains.per_joint(n)
    boost = np.where(excited & ~trusted, 1.0, BOOST)
    kp, bw = kp0 * boost, bw0 * boost
    placed = ""
    if "placement" not in leave_out and gains.gear_stiffness_nm_rad:
        # an elastic gear: the velocity loop stays below the gear's anti-resonance with the link's inertia at this
        # pose as identified (the rotor's excluded); where the boost would cross it the joint keeps its default
        # bandwidth (placed below the anti-resonance at the workspace's worst inertia) or less
        link = np.maximum(inertia_kg_m2 - np.array(gains.rotor_inertia_kg_m2), 1e-9)
        anti = np.sqrt(np.array(gains.gear_stiffness_nm_rad) / link)
        held = bw > anti
        bw = np.where(held, np.minimum(bw0, anti), bw)
        kp = np.where(held, np.minimum(kp0, POSITION_OVER_VELOCITY * bw), kp)
        if np.any(held):
            placed = "below the gears' anti-resonance on joint " + ", ".join(str(j + 1) for j in np.nonzero(held)[0])
        # a joint whose gains its gear limits keeps the nominal friction: the Coulomb term switches with the
        # demanded speed, and a larger one rings the gear (measured: it slows the settling on the IRB 2400's j1-j3)
        factor[held | (bw0 < gains.velocity_bw_rad_s)] = 1.0
    if "feedforward" in leave_out:
        d_inertia, d_viscous, d_offset = np.zeros(n), np.zeros(n), np.zeros(n)
    notes = [placed] if placed else []
    if not np.all(trusted | ~excited):
        notes.append("inertia not trusted on joint " + ", ".join(str(j + 1) for j in np.nonzero(excited & ~trusted)[0]))
    return _tuning(gains, kp, bw, ratio, d_inertia, d_viscous, d_offset, extra_kg, "; ".join(notes),
                   tuple(factor.tolist()) if with_coulomb else (), float(np.median(sharp)) if sharp else 0.0)


def _sharpness(qdd: np.ndarray, qd: np.ndarray, residual: np.ndarray) -> float:
    """The Coulomb term's smoothing speed (of FRICTION_SMOOTH_CANDIDATES_RAD_S) that fits one joint's residual best."""
    def misfit(smooth_rad_s: float) -> float:
        columns = np.column_stack([qdd, qd, np.ones(len(qd)), np.tanh(qd / smooth_rad_s)])
        fit, *_ = np.linalg.lstsq(columns, residual, rcond=None)
        return float(np.sum((columns @ fit - residual) ** 2))
    return min(FRICTION_SMOOTH_CANDIDATES_RAD_S, key=misfit)


def _inertia(model: Callable[..., Any], q0: tuple[float, ...], load_kg: float) -> np.ndarray:
    """The model's M_ii at q0 with a payload of load_kg at the flange."""
    n = len(q0)
    zero = (0.0,) * n
    at_rest = np.array(model(tuple(q0), zero, zero, load_kg))
    return np.array([model(tuple(q0), zero, tuple(1.0 if i == j else 0.0 for i in range(n)), load_kg)[j]
                     - at_rest[j] for j in range(n)])


def _tuning(gains: ServoGains, kp: np.ndarray, bw: np.ndarray, ratio: np.ndarray, d_inertia: np.ndarray,
            d_viscous: np.ndarray, d_offset: np.ndarray, load_kg: float, note: str,
            friction_factor: tuple[float, ...] = (), friction_smooth_rad_s: float = 0.0) -> ServoTuning:
    ibw = np.full(len(ratio), gains.integral_bw_rad_s)
    friction = f", friction = {_numbers(np.array(friction_factor), 2)} x nominal" if friction_factor else ""
    if friction_smooth_rad_s:
        friction += f" turning within {friction_smooth_rad_s:g} rad/s"
    label = (f"tuning(bandwidth = {_numbers(bw, 0)} rad/s, inertia = {_numbers(ratio, 3)} x model, "
             f"load = {load_kg:.1f} kg{friction}, offset = {_numbers(d_offset, 1)} N m" + (f", {note}" if note else "") + ")")
    return ServoTuning(tuple(kp.tolist()), tuple((bw * ratio).tolist()), tuple(ibw.tolist()), tuple(d_inertia.tolist()),
                       tuple(d_viscous.tolist()), tuple(d_offset.tolist()), label, float(load_kg), friction_factor,
                       friction_smooth_rad_s)


def _numbers(values: np.ndarray, digits: int) -> str:
    """`[1, 2.5, 0]`: rounded, without trailing zeros."""
    def one(v: float) -> str:
        text = f"{round(float(v), digits) + 0.0:.{digits}f}"
        return text.rstrip("0").rstrip(".") if "." in text else text
    return "[" + ", ".join(one(v) for v in values) + "]"
