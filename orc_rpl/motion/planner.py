"""Planning: motion specs and parameters into dense paths, limits and trajectories; the store of saved plans."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import CubicSpline

from orc_rpl.errors import PlanningError, UsageError
from orc_rpl.motion.kinematics import Kinematics
from orc_rpl.motion.paths import DensePath, cartesian_path, function_path, joint_segments
from orc_rpl.motion.blending import blend
from orc_rpl.motion.gear_steps import GearSteps
from orc_rpl.motion.short_move import DEFAULT_JERK_PER_S, ShortLimits, constant_dynamics_accel
from orc_rpl.motion.specs import CartesianMotion, FunctionMotion, JointMotion, Known, Motion, Params
from orc_rpl.motion.timing import TimingLimits, parameterize
from orc_rpl.motion.trajectory import SplinePath, Trajectory

#: share of the torque limits the planner may use; the rest is the servo's, for feedback
TORQUE_SHARE = 0.9
#: share of the limits a motion that is only `almost` known may use: the rest is left for sensor corrections
ALMOST_SHARE = 0.9
#: share for a `partly` known motion: its nominal path is a guess the sensor will change
PARTLY_SHARE = 0.5


@dataclass(slots=True)
class Plan:
    """A planned move: its path pieces (stops between them), its limits and, when saved, its first trajectory."""

    owner: int
    motion: Motion
    params: Params
    pieces: list[DensePath]              #: consecutive paths; the robot stops between them (FINE via points)
    limits: TimingLimits
    start_q: np.ndarray
    end_q: np.ndarray
    tool: np.ndarray | None
    timed: Trajectory | None = None      #: a trajectory fixed in time (function of t), not re-timed
    saved_first: Trajectory | None = None  #: the first piece timed from rest (computation=save)
    first_chord_rad: float = 0.0         #: joint chord of the first segment (a blend into it takes half at most)
    last_chord_rad: float = 0.0          #: joint chord of the last segment (a blend out of it takes half at most)
    notes: list[str] = field(default_factory=list)


class Planner:
    """Turns motion requests into plans and trajectories for one arm at one motion-cycle period."""

    def __init__(self, kin: Kinematics, dt_s: float, sub: int) -> None:
        self.kin = kin
        self.arm = kin.arm
        self.dt_s = dt_s
        self.sub = sub
        self._saved: dict[int, Plan] = {}
        #: TCP speed every move keeps (manual mode: 0.25 m/s); None: no cap
        self.tcp_speed_cap_m_s: float | None = None
        #: torque the model's nominal friction may take at full speed (N m per joint), kept out of the
        #: torque limits (toppra's torque bound has no term linear in the path speed); zeros: no friction
        self.friction_reserve_nm: np.ndarray | float = 0.0
        #: windows (s) over which a path trajectory from rest has its time scaling averaged (elastic gears), () none
        self.smoothing_s: tuple[float, ...] = ()
        #: elastic gears under state feedback: a trajectory from rest averaged over as much of those windows as its
        #: steps' twist of the gears calls for; None: over the whole windows
        self.gear_steps: GearSteps | None = None

    # -- limits -----------------------------------------------------------------

    def limits(self, params: Params, tool: np.ndarray | None = None) -> TimingLimits:
        """The timing limits a move's parameters ask for."""
        share = {Known.ALMOST: ALMOST_SHARE, Known.PARTLY: PARTLY_SHARE}.get(params.known, 1.0)
        load = params.load_kg
        arm = self.arm

        # toppra calls this three times per grid point: the bare RNEA, the payload set only when it differs
        rnea = arm.inverse_dynamics_function() if hasattr(arm, "inverse_dynamics_function") else None
        payload = (float(load), 0.0, 0.0, 0.0)

        def inverse_dynamics(q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
            if rnea is None:
                return np.array(arm.inverse_dynamics(q, qd, qdd, load))
            # The planner's own model (virtual.py gives the servo another): its payload may be set here.
            if arm.payload != payload:
                arm.set_payload(load)
            return rnea(q, qd, qdd)  # a new array each call

        rnea_rows = arm.inverse_dynamics_rows_function() if hasattr(arm, "inverse_dynamics_rows_function") else None

        def inverse_dynamics_rows(q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, out: np.ndarray) -> None:
            if arm.payload != payload:
                arm.set_payload(load)
            rnea_rows(q, qd, qdd, out)  # type: ignore[misc]

        speed = params.speed_m_s
        frac = params.speed_fraction
        cap = self.tcp_speed_cap_m_s
        tcp: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None
        if speed is not None or cap is not None:

            def tcp_limit(owner: np.ndarray, s: np.ndarray) -> np.ndarray:
                out = []
                for v in s:
                    asked = params.speed_m_s_at(float(v))
                    limit = min(math.inf if asked is None else asked, math.inf if cap is None else cap)
                    out.append(limit * params.speed_fraction_at(float(v)))
                return np.array(out)

            tcp = tcp_limit

        frac_fn = None if not callable(frac) and frac == 1.0 else (lambda owner, s: np.array([params.speed_fraction_at(float(v)) for v in s]))
        return TimingLimits(
            qd_max=arm.qd_max * share,
            qdd_max=arm.qdd_max * params.accel_fraction * share,
            tau_max=(arm.tau_max * TORQUE_SHARE - self.friction_reserve_nm) * share,
            inverse_dynamics=inverse_dynamics,
            inverse_dynamics_rows=inverse_dynamics_rows if rnea_rows is not None else None,
            tcp_jacobian=self._tcp_jacobian(tool) if tcp is not None else None,
            tcp_speed_m_s=tcp,
            speed_fraction=frac_fn,
            load_kg=load,
        )

    def _tcp_jacobian(self, tool: np.ndarray | None) -> Callable[[np.ndarray], np.ndarray]:
        """The (3, n) linear TCP Jacobian at q, for the speed bound at every grid point: the tool is checked once here."""
        arm = self.arm
        checked = None if tool is None else arm.transform(tool)
        linear_jacobian = arm.linear_jacobian_unchecked
        return lambda q: linear_jacobian(q, checked)

    def short_limits(self, q: np.ndarray, params: Params) -> ShortLimits:
        """Short-move limits: the dynamics at the start taken as constant for the whole move."""
        arm = self.arm
        gravity = np.array(arm.inverse_dynamics(q, np.zeros_like(q), np.zeros_like(q), params.load_kg))
        inertia = np.diag(arm.mass_matrix(q, params.load_kg))
        qdd = constant_dynamics_accel(arm.qdd_max * params.accel_fraction, arm.tau_max * TORQUE_SHARE - self.friction_reserve_nm,
                                      gravity, inertia)
        frac = params.speed_fraction_at(0.0)
        return ShortLimits(arm.qd_max * frac, qdd, qdd * DEFAULT_JERK_PER_S)

    # -- geometry -----------------------------------------------------------------

    def plan(self, owner: int, motion: Motion, params: Params, q_start: np.ndarray) -> Plan | None:
        """The plan of a move starting at q_start; None for a zero-length move."""
        q_start = np.asarray(q_start, dtype=float)
        tool = motion.tool
        limits = self.limits(params, tool)
        timed = None
        if isinstance(motion, JointMotion):
            if len(motion.target_rad) != self.kin.n:
                raise UsageError(f"joint target has {len(motion.target_rad)} values; the robot has {self.kin.n} joints")
            segs = joint_segments(self.kin, q_start, motion, owner)
            pieces = self._join(segs, params.zone_m, tool)
            chords = [s.length_rad() for s in segs] or [0.0]
        elif isinstance(motion, CartesianMotion):
            dense = cartesian_path(self.kin, q_start, motion, owner)
            pieces = [] if dense is None else [dense]
            chords = [dense.length_rad() if dense is not None else 0.0]
        elif isinstance(motion, FunctionMotion):
            if motion.variable == "t":
                timed = self._function_of_time(motion, q_start, owner)
                pieces = [timed.path.dense]
            else:
                pieces = [function_path(self.kin, q_start, motion, owner)]
            chords = [pieces[0].length_rad()]
        else:
            raise UsageError(f"move() takes a JointMotion, CartesianMotion or FunctionMotion, not {type(motion).__name__}")
        if not pieces:
            return None
        end_q = timed.q_f[-1] if timed is not None else pieces[-1].q[-1]
        return Plan(owner, motion, params, pieces, limits, q_start, np.array(end_q), tool, timed,
                    first_chord_rad=chords[0], last_chord_rad=chords[-1])

    def _join(self, segs: list[DensePath], zone_m: float, tool: np.ndarray | None) -> list[DensePath]:
        """Blend a motion's own via points with its zone; with FINE they become separate pieces."""
        if not segs:
            return []
        pieces = [segs[0]]
        for prev, seg in zip(segs, segs[1:]):
            joined = blend(self.kin, pieces[-1], seg, zone_m, 1, tool, prev.length_rad(), seg.length_rad()) if zone_m > 0 else None
            if joined is None:
                pieces.append(seg)
            else:
                pieces[-1] = joined
        return pieces

    def _function_of_time(self, motion: FunctionMotion, q_start: np.ndarray, owner: int) -> Trajectory:
        """A motion whose pose is a function of time: IK every motion cycle, a spline in time between."""
        cycles = max(1, math.ceil(motion.duration_s / self.dt_s - 1e-9))
        t = np.linspace(0.0, motion.duration_s, cycles + 1)
        poses = np.stack([motion.pose_at(float(v)) for v in t])
        qs = self.kin.ik_along(poses, q_start, motion.tool, "function motion of time")
        spline = CubicSpline(t, qs, bc_type="clamped")
        tf = np.minimum(np.arange(cycles * self.sub + 1) * (self.dt_s / self.sub), motion.duration_s)
        q, qd, qdd = spline(tf), spline(tf, 1), spline(tf, 2)
        over = np.max(np.abs(qd) / self.arm.qd_max)
        if over > 1.0 + 1e-6:
            raise PlanningError(f"function motion of time: it asks for {100 * over:.0f} % of a joint's speed limit; give it more time")
        s = t / motion.duration_s
        dense = DensePath(qs, poses[:, :3, 3].copy(), np.full(len(qs), owner), s)
        return Trajectory(
            self.dt_s, self.sub, SplinePath(dense), tf / motion.duration_s, np.zeros(len(tf)), q, qd, qdd,
            np.full(cycles + 1, owner), s, motion.duration_s, blendable=False, kind="timed",
        )

    # -- timing -------------------------------------------------------------------

    def time(self, dense: DensePath, limits: TimingLimits, sd_start: float = 0.0, min_duration_s: float | None = None,
             whole_averaging: bool = False) -> Trajectory:
        """Time a dense path (time-optimal, or the fallback profile if toppra fails); from rest, averaged over
        `smoothing_s` (elastic gears: the averaging is part of the planning, on the plan-ahead worker too), over
        the whole windows with `whole_averaging` even where `gear_steps` would scale them."""
        traj, _ = parameterize(SplinePath(dense), limits, self.dt_s, self.sub, sd_start, 0.0, min_duration_s,
                               smoothing_s=self.smoothing_s, gear_steps=None if whole_averaging else self.gear_steps)
        return traj

    # -- computation = save / done ---------------------------------------------------

    def save(self, descriptor: int, plan: Plan) -> None:
        """Store a plan (its first piece timed from rest) under a descriptor, replacing what was there."""
        if plan.timed is None:
            plan.saved_first = self.time(plan.pieces[0], plan.limits, 0.0, plan.params.time_s,
                                         plan.params.whole_averaging)
        self._saved[descriptor] = plan

    def recall(self, descriptor: int, motion: Motion, q_start: np.ndarray) -> Plan | None:
        """The saved plan if it is for the same motion from the same start; else None (plan `during`)."""
        plan = self._saved.get(descriptor)
        if plan is None or plan.motion != motion or not np.allclose(plan.start_q, q_start, atol=1e-9, rtol=0.0):
            return None
        return plan


def combine(limits: dict[int, TimingLimits]) -> TimingLimits:
    """Limits for a path shared by several moves (a blend): joint limits the tightest, speeds per owning move."""
    if len(limits) == 1:
        return next(iter(limits.values()))
    items = list(limits.values())

    def per_owner(attr: str, default: float):  # type: ignore[no-untyped-def]
        if all(getattr(lim, attr) is None for lim in items):
            return None

        def fn(owner: np.ndarray, s: np.ndarray) -> np.ndarray:
            out = np.full(len(s), default)
            for o, lim in limits.items():
                f = getattr(lim, attr)
                mask = owner == o
                if f is not None and mask.any():
                    out[mask] = f(owner[mask], s[mask])
            return out

        return fn

    heavy = max(items, key=lambda lim: lim.load_kg)  # the heavier payload bounds the torques of both
    jac = next((lim.tcp_jacobian for lim in items if lim.tcp_jacobian is not None), None)
    return TimingLimits(
        qd_max=np.min([lim.qd_max for lim in items], axis=0),
        qdd_max=np.min([lim.qdd_max for lim in items], axis=0),
        tau_max=np.min([lim.tau_max for lim in items if lim.tau_max is not None], axis=0),
        inverse_dynamics=heavy.inverse_dynamics,
        inverse_dynamics_rows=heavy.inverse_dynamics_rows,
        tcp_jacobian=jac,
        tcp_speed_m_s=per_owner("tcp_speed_m_s", math.inf),
        speed_fraction=per_owner("speed_fraction", 1.0),
        load_kg=heavy.load_kg,
    )

