"""GRINDMOVE without a force flange: the arm presses and feels the grinding force itself (thesis 2.1, 3.4).

No extra sensor. The normal force is read from the arm's own motor torques: the controller's model of the
torques the motion needs (rigid body with the acceleration from the encoder angles, the friction estimate with
its warm-up) minus the measured ones, through the TCP's Jacobian, along the path normal n. That estimate is off
by tens of newtons on the realistic plant (the friction's level, the static friction of a joint at rest), but
most of its error repeats pass after pass at the same path coordinate (the same speeds, directions and turn
points). So each grinding move is first run in free air, lifted LIFT_M off the edge along n: its estimate
against the arc length is the move's signature, and in contact the force is the estimate minus the signature
at the same arc length, averaged over AVERAGE_CYCLES cycles (the torque noise).

The model's torque needs the links' acceleration; the controller measures the motors'. Through rigid gears the two
are the same. Through elastic gears they are the same only below the gears' anti-resonance: above it a rotor,
held stiffly by its servo, shakes against its gear while its link hardly follows, and the model's inertia times
the rotor's acceleration reads as a contact force of hundreds of newtons (on the IRB 2400's elastic gears the
loop rang with it and never felt the casting). So the acceleration is the motors' averaged over one period of the
gears' lowest anti-resonance at the links' inertia (`features/gears.py` `gear_period_cycles`): a window of one cycle on rigid gears.

The force loop moves the arm's path along -n (into the part) by an offset u, set at the motion rate as a path
correction (TRACKMOVE's way):

    u <- clip(u + K dt (F_cmd(s) - F_estimated), -10 mm, +10 mm),    K = ADMITTANCE_M_PER_N_S

The offset reaches the TCP through the servo's position loop (its lag) and the estimate's average (its delay),
so K is a tenth of the flange's; the tip rides on the edge and its normal position, the TCP the encoders give,
is CatchBulge's profile (the thesis' "actual joint positions and the kinematics").
"""

from __future__ import annotations

import dataclasses
import math
from collections import deque
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np

from orc_rpl.application.features.gears import gear_period_cycles
from orc_rpl.application.runtime import BehaviourError, MotionRequest, MotionView
from orc_rpl.motion.gear_friction import SIGN_SMOOTH_RAD_S  # the sharp Coulomb term of the friction estimate
from orc_rpl.robot.friction import friction_torque_nm
from orc_rpl.world.pose import Pose

#: How far the signature pass is lifted off the edge along n (m): clear of bulges up to that high (a higher one
#: would touch the signature pass and spoil it).
LIFT_M = 0.005
#: Admittance gain of the arm's force loop (m of path offset per N of force error and second): the loop's
#: time constant on the cell's 50 N/mm casting is 1 / (K k).
ADMITTANCE_M_PER_N_S = 2.5e-4
#: The offset's range (m).
OFFSET_LIMIT_M = 0.01
#: The estimate is averaged over this many motion cycles (the torque noise is several newtons a cycle).
AVERAGE_CYCLES = 5
#: A joint slower than this sticks (static friction: it holds any torque up to its Coulomb friction, which no
#: model of the speed tells, and when it breaks away depends on the load): while a joint that carries the normal
#: force (its lever at least LEVER_SHARE of the largest) sticks, now or in the signature near this arc length,
#: the loop holds its offset.
STICK_RAD_S = 0.004
LEVER_SHARE = 0.1
#: While it holds, the offset goes to the median of the last PRESSING_CYCLES offsets whose force was within
#: PRESSING_FRACTION of the command.
PRESSING_CYCLES = 100
PRESSING_FRACTION = 0.1
#: How near (m of arc length) a sticking sample of the signature holds the loop.
STICK_NEAR_M = 0.004
#: The arm's force loop settles over a few oscillations of its own: the contact has settled when its force has
#: stayed within GRINDMOVE's settled fraction of the command this many cycles in a row.
SETTLED_CYCLES = 25


class ArmForce:
    """The force along n on the TCP from the motor torques, once a motion cycle (N, pressing on the part > 0)."""

    def __init__(self, robot: Any, tool: Pose, normal: np.ndarray) -> None:
        for needed in ("jacobian_linear", "torques", "joint_speeds", "inverse_dynamics"):
            if not callable(getattr(robot, needed, None)):
                raise BehaviourError("GRINDMOVE without a force flange presses with the arm and reads the grinding "
                                     "force from its motor torques: this robot has no joint servo to read "
                                     "(install a Grinder WITH FORCE_IN = AnalogIn[n] WITH STROKE = AnalogOut[n])")
        self.robot, self.tool, self.normal = robot, tool, normal
        self._angles: deque[tuple[float, np.ndarray]] = deque(maxlen=3)
        self._accelerations: deque[np.ndarray] | None = None  #: made at the first reading (its pose's window)
        self.sticking = False  #: a joint carrying the normal force sticks (set by update)

    def _friction_nm(self, speed: np.ndarray) -> np.ndarray:
        """The friction the joints need now: the controller's warm-up estimate, else the servo's nominal one."""
        state = getattr(self.robot, "friction_state", lambda: None)()
        if state is not None:
            coulomb, viscous = state.coulomb_nm, state.viscous_nm_s
        else:
            nominal = getattr(self.robot, "servo_friction", lambda: None)()
            if nominal is None:
                return np.zeros_like(speed)
            coulomb, viscous = nominal
        return friction_torque_nm(coulomb, viscous, speed, SIGN_SMOOTH_RAD_S)

    def update(self) -> float:
        robot = self.robot
        q, speed = np.array(robot.joints()), np.array(robot.joint_speeds())
        self._angles.append((robot.time_s(), q))
        qdd = np.zeros_like(q)
        if len(self._angles) == 3:
            (t0, q0), (t1, q1), (t2, q2) = self._angles
            if t2 > t1 > t0:
                qdd = ((q2 - q1) / (t2 - t1) - (q1 - q0) / (t1 - t0)) / (0.5 * (t2 - t0))
        if self._accelerations is None:
            self._accelerations = deque(maxlen=gear_period_cycles(robot, q))
        self._accelerations.append(qdd)
        qdd = np.mean(self._accelerations, axis=0)
        needed = np.array(robot.inverse_dynamics(tuple(q), tuple(speed), tuple(qdd), 0.0)) + self._friction_nm(speed)
        external = needed - np.array(robot.torques())  # what the contact takes off the motors: J^T f
        jacobian_t = robot.jacobian_linear(self.tool).T
        lever = np.abs(jacobian_t @ self.normal)
        self.sticking = bool(np.any((lever >= LEVER_SHARE * lever.max()) & (np.abs(speed) < STICK_RAD_S)))
        force = np.linalg.lstsq(jacobian_t, external, rcond=None)[0]
        return float(np.dot(force, self.normal))


class Signature:
    """A move's force estimate in free air against the arc length (m along the nominal path)."""

    def __init__(self) -> None:
        self.arcs: list[float] = []
        self.forces: list[float] = []
        self.stuck: list[float] = []  #: arc lengths where a joint carrying the normal force stuck
        self._sorted: tuple[np.ndarray, np.ndarray] | None = None

    def add(self, arc_m: float, force_n: float, sticking: bool) -> None:
        self.arcs.append(arc_m)
        self.forces.append(force_n)
        if sticking:
            self.stuck.append(arc_m)
        self._sorted = None

    def stuck_near(self, arc_m: float) -> bool:
        return any(abs(arc_m - a) <= STICK_NEAR_M for a in self.stuck)

    def at(self, arc_m: float) -> float:
        if self._sorted is None:
            order = np.argsort(self.arcs, kind="stable")
            self._sorted = (np.array(self.arcs)[order], np.array(self.forces)[order])
        arcs, forces = self._sorted
        return float(np.interp(arc_m, arcs, forces)) if len(arcs) else 0.0


class ArmForceLoop:
    """The admittance law on the arm's path offset along -n, one step a motion cycle (the flange's ForceLoop's
    interface): it lifts off the edge between moves, and runs each grinding move in free air first."""

    settle_cycles = SETTLED_CYCLES
    #: A pass over a bulge starts at its end, reached lifted off the edge (pressed_move).
    stays_on_edge = False

    def __init__(self, robot: Any, force: Callable[[float], float], tool: Pose, watch: Any, geometry: Any,
                 arc_of: Callable[[], float]) -> None:
        """`geometry`: the nominal path (its outward `normal`, `pose_at(arc_m)`); `arc_of()`: the TCP's arc length
        on it now."""
        self.robot, self.force, self.normal = robot, force, geometry.normal
        self.geometry, self.arc_of = geometry, arc_of
        self.estimate = ArmForce(robot, tool, self.normal)
        self.stroke_m = 0.0                     #: the path offset u toward the part (m)
        self.planned_m = 0.0                    #: the offset the running move was planned at
        self.signature: Signature | None = None  #: the running move's (None: recording one in free air)
        self.signatures: dict[tuple[float, float], Signature] = {}  #: by the moves' (start, end) arc lengths
        self._recent: deque[float] = deque(maxlen=AVERAGE_CYCLES)
        self._measured = 0.0
        self._pressing: deque[float] = deque(maxlen=PRESSING_CYCLES)  #: offsets that pressed with the command
        self.watch = watch                      #: the instability watch (ForceLoop's window of errors)

    def measured_n(self) -> float:
        return self._measured

    def tip_offset_m(self) -> float:
        return 0.0  # the grinding tip is the TCP: the offset is in the measured TCP already

    def unstable(self) -> str | None:
        return self.watch.unstable()

    def record(self, arc_m: float) -> None:
        """A free-air cycle of a signature pass."""
        raw = self.estimate.update()
        if self.signature is not None:
            self.signature.add(arc_m, raw, self.estimate.sticking)

    def step(self, s: float, arc_m: float) -> tuple[float, float]:
        """Read the force, move the path offset; (commanded, measured) force."""
        raw = self.estimate.update()
        command = self.force(s)
        signature = self.signature
        if self.estimate.sticking or (signature is not None and signature.stuck_near(arc_m)):
            # the estimate means nothing here: the offset goes to the one that pressed with the command on the edge
            # so far (at the rate the loop would move it in free air), and the average starts anew after
            self._recent.clear()
            if self._pressing:
                held = sorted(self._pressing)[len(self._pressing) // 2]
                step = ADMITTANCE_M_PER_N_S * self.robot.dt_s * abs(command)
                self.stroke_m += min(step, max(-step, held - self.stroke_m))
            return command, self._measured
        now = raw - (signature.at(arc_m) if signature is not None else 0.0)
        self._recent.append(now)
        measured = self._measured = sum(self._recent) / len(self._recent)
        self.watch.observe(command, now)  # each cycle's own reading: an oscillation faster than the average shows
        if abs(measured - command) <= PRESSING_FRACTION * command:
            self._pressing.append(self.stroke_m)
        self.stroke_m = min(OFFSET_LIMIT_M, max(-OFFSET_LIMIT_M, self.stroke_m + ADMITTANCE_M_PER_N_S
                                                * self.robot.dt_s * (command - measured)))
        return command, measured

    def correction(self, view: MotionView) -> tuple[float, float, float]:
        """The TCP's offset from the running move's planned path (which lies `planned_m` inside the part)."""
        return tuple(float(x) for x in -(self.stroke_m - self.planned_m) * self.normal)  # type: ignore[return-value]

    def retract(self) -> None:
        self.stroke_m = 0.0

    def offset(self, pose: Pose, lift_m: float) -> Pose:
        """`pose` moved along n by lift_m (out of the part)."""
        dx, dy, dz = (float(d) for d in lift_m * self.normal)
        return pose.offset(dx, dy, dz)

    def approach(self, start: Pose) -> Pose:
        """Where the move to the path's start goes: lifted off it (pressed_move lowers the arm)."""
        return self.offset(start, LIFT_M)

    def leave(self, base: MotionRequest, end: Pose) -> Iterator[Any]:
        """The path is done: the offset back to 0 and the path's end on the nominal edge (no force on a ground
        edge)."""
        self.retract()
        yield from run_to(self.robot, base, end)

    def nothing_ground(self, settled: bool) -> str | None:
        """Why nothing was ground (the contact never `settled`: never pressed with the command for
        SETTLED_CYCLES in a row), or None."""
        if settled:
            return None
        return ("the arm felt no contact force along the whole path: nothing was ground "
                "(no casting in the cell, or the path is not on its edge)")

    def pressed_move(self, base: MotionRequest, start_m: float, end_m: float, target: Pose,
                     via: tuple[Pose, ...]) -> Iterator[Any]:
        """A grinding move from arc length start_m to `target` (at end_m): lifted off the edge where it is (on
        the nominal path), its signature in free air (once per start and end), then lowered onto the start to the
        offset the loop holds and the move in contact with the correction; returns the contact move's ticket."""
        here = self.geometry.pose_at(self.arc_of())
        start = self.geometry.pose_at(start_m)
        key, signatures, arc_of = (round(start_m, 4), round(end_m, 4)), self.signatures, self.arc_of
        yield from run_to(self.robot, base, self.offset(here, LIFT_M), ())
        if key not in signatures:
            yield from run_to(self.robot, base, self.offset(start, LIFT_M), ())
            self.signature = signatures[key] = Signature()
            self._recent.clear()
            ticket = yield dataclasses.replace(base, target=self.offset(target, LIFT_M),
                                               via=tuple(self.offset(p, LIFT_M) for p in via))
            while not ticket.done:
                yield None
                self.record(arc_of())
            _check(ticket)
        yield from run_to(self.robot, base, self.offset(start, LIFT_M), ())
        self.planned_m = self.stroke_m
        yield from run_to(self.robot, base, self.offset(start, -self.planned_m), ())
        self.signature = signatures[key]
        self._recent.clear()
        return (yield dataclasses.replace(base, target=self.offset(target, -self.planned_m),
                                          via=tuple(self.offset(p, -self.planned_m) for p in via),
                                          correction=self.correction))


def run_to(robot: Any, base: MotionRequest, target: Pose, via: tuple[Pose, ...] = ()) -> Iterator[Any]:
    """A move not grinding (lifting, lowering, back to a start), to its end; none when the TCP is there."""
    tcp = robot.tcp_pose(base.tool)
    if not via and math.dist((tcp.x, tcp.y, tcp.z), (target.x, target.y, target.z)) < 1e-4:
        return
    ticket = yield dataclasses.replace(base, target=target, via=via)
    while not ticket.done:
        yield None
    _check(ticket)


def _check(ticket: Any) -> None:
    if ticket.outcome == "fault":
        raise ticket.error if ticket.error is not None else BehaviourError("a motion of GRINDMOVE failed")
