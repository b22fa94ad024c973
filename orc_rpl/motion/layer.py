"""The motion layer (thesis 4.3, 5.2): move() and short_move(), stops, modes, waiting and the acquire services."""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from orc_rpl.errors import UsageError
from orc_rpl.listeners import Listeners
from orc_rpl.motion import services
from orc_rpl.motion.actions import Actions, MoveSignal
from orc_rpl.motion.ahead import PLANNED_AHEAD, PlanAhead
from orc_rpl.motion.backend import Backend
from orc_rpl.motion.braking import brake
from orc_rpl.motion.handle import MoveHandle
from orc_rpl.motion.kinematics import Kinematics
from orc_rpl.motion.paths import DensePath
from orc_rpl.motion.pipeline import MotionPipeline
from orc_rpl.motion.planner import Planner
from orc_rpl.motion.short_move import stop_trajectory
from orc_rpl.motion.thermal import ThermalModel
from orc_rpl.motion.trajectory import Trajectory
from orc_rpl.motion.specs import DEFAULT_PARAMS, CartesianMotion, Computation, JointMotion, Mode, Motion, MoveStatus, Params


class MotionLayer(MotionPipeline):
    """Plans and executes moves on one arm; time advances only through tick(), wait() and run_until_idle()."""

    def __init__(self, kin: Kinematics, backend: Backend, motion_period_s: float = 0.004,
                 realtime: bool = False, logger: Any = None) -> None:
        sub = round(motion_period_s / backend.servo_period_s)
        if sub < 1 or abs(sub * backend.servo_period_s - motion_period_s) > 1e-9:
            raise UsageError(f"motion_period_s={motion_period_s} must be a whole number of servo periods ({backend.servo_period_s} s)")
        self.kin, self.backend, self.dt_s, self.sub = kin, backend, motion_period_s, sub
        self.planner = Planner(kin, motion_period_s, sub)
        self.realtime, self.logger = realtime, logger
        self.mode = Mode.RUN
        q = np.array(backend.q(), dtype=float)
        self._q_ref, self._qd_ref, self._qdd_ref = q, np.zeros_like(q), np.zeros_like(q)
        self._hold_cache: tuple[np.ndarray, ...] | None = None
        self._traj: Trajectory | None = None
        self._k = 0
        self._traj_t0 = 0.0
        self._in_traj: list[MoveHandle] = []
        self._queue: deque[MoveHandle] = deque()
        self._active: MoveHandle | None = None
        self._settling: tuple[MoveHandle, float] | None = None
        self._continuous: list[tuple[Actions, MoveHandle]] = []
        self._next_id = 1
        self._stop_by = "stop_move"
        self._control_load_kg = 0.0
        self._tuning: Any = None  # the servo tuning in use (None: the default gains)
        self._wall_start: float | None = None
        self.cycles = 0
        #: plans the next move on a worker thread while this one runs (None: every move is planned when requested)
        self.ahead: PlanAhead | None = None
        #: the planned-path signal: each listener is told (move id, planned TCP positions (N, 3) in m) when a
        #: move is accepted, before it starts (a 3D view draws the path the robot is about to take)
        self.plan_listeners: Listeners[[int, np.ndarray]] = Listeners()
        # thesis 4.5, alternative 3: the thermal load estimate is part of the standard motion cycle
        tau_max = getattr(kin.arm, "tau_max", None)
        self.thermal = None if tau_max is None else ThermalModel.for_arm(tau_max, motion_period_s)

    # -- reading the robot --------------------------------------------------------------

    def current_q(self) -> np.ndarray:
        """Measured joint positions."""
        return np.array(self.backend.q())

    def reference_q(self) -> np.ndarray:
        """Commanded joint positions."""
        return self._q_ref.copy()

    def tcp_pose(self, tool: np.ndarray | None = None) -> np.ndarray:
        """Measured TCP pose (4x4, world)."""
        return self.kin.fk(self.backend.q(), tool)

    def thermal_load(self) -> np.ndarray:
        """Thermal load of each motor (1.0 = its continuous limit), estimated from the torque since the start."""
        if self.thermal is None:
            return np.zeros(len(self._q_ref))
        return self.thermal.load.copy()

    def progress_s(self) -> float:
        """The running move's path coordinate (1.0 when none runs)."""
        return self._active.s if self._active is not None else 1.0

    def idle(self) -> bool:
        """No move running, settling or waiting."""
        return self._traj is None and not self._queue and self._settling is None

    def pending(self) -> int:
        """Moves not yet done (running, settling or queued)."""
        return len({h.id for h in self._in_traj if not h.done} | {h.id for h in self._queue}) + (self._settling is not None)

    # -- requesting motion --------------------------------------------------------------

    def move(self, motion: Motion, params: Params = DEFAULT_PARAMS, actions: Actions | None = None) -> MoveHandle:
        """Request a move; it is planned now and runs as time advances (returns at once, status spawned).

        Raises Unreachable, JointLimit, PlanningError or UsageError when the move cannot be planned.
        """
        return self._request(motion, params, actions, short=False)

    def short_move(self, motion: JointMotion | CartesianMotion, params: Params = DEFAULT_PARAMS,
                   actions: Actions | None = None) -> MoveHandle:
        """A short move (ShortMove): jerk-limited ruckig trajectory, dynamics taken as constant, always FINE."""
        if not isinstance(motion, JointMotion | CartesianMotion) or (isinstance(motion, JointMotion) and motion.via_rad):
            raise UsageError("short_move takes a JointMotion without via points or a CartesianMotion")
        return self._request(motion, params, actions, short=True)

    def _request(self, motion: Motion, params: Params, actions: Actions | None, short: bool) -> MoveHandle:
        h = MoveHandle(self._next_id, motion, params, actions if actions is not None else Actions(), short=short)
        self._next_id += 1
        if self.mode not in (Mode.RUN, Mode.TRACK):
            h.status, h.done = MoveStatus.ILLEGAL, True
            return h
        q_start = self._tail_q()
        plan = None
        if params.computation is Computation.DONE:
            assert params.descriptor is not None
            if params.descriptor < 0 and self.ahead is not None:  # planned ahead on the worker
                plan = self.ahead.take(-params.descriptor, motion, q_start, self.planner)
            else:
                plan = self.planner.recall(params.descriptor, motion, q_start)
            h.replanned_during = plan is None
        if plan is None:
            if self.ahead is not None:
                self.ahead.counts.at_start += 1
            plan = self.planner.plan(h.id, motion, params, q_start)
        else:
            plan = _reowned(plan, h.id)
        if plan is None:  # zero-length: nothing to do
            h.status, h.done, h.s = MoveStatus.READY, True, 1.0
            h.start_time_s = h.end_time_s = self.now_s()
            h.signal.signal("done", self.now_s())
            return h
        if params.computation is Computation.SAVE:
            assert params.descriptor is not None
            self.planner.save(params.descriptor, plan)
            h.status, h.done = MoveStatus.READY, True
            return h
        h.plan, h.pieces_left = plan, list(plan.pieces)
        if self.plan_listeners and plan.pieces:
            tcp_m = np.vstack([piece.tcp for piece in plan.pieces])
            self.plan_listeners(h.id, tcp_m)
        self._queue.append(h)
        self._admit()
        return h

    def plan_ahead(self, motion: Motion, params: Params = DEFAULT_PARAMS) -> int | None:
        """Start planning `motion` (to follow every accepted move) on the worker; submit it later with
        `Params(computation=Computation.DONE, descriptor=<the returned value>)`, best once `ahead_ready()`.
        None: not planned ahead (no worker, or the motion is only partly or not known: it is planned when requested)."""
        if self.ahead is None or params.known not in PLANNED_AHEAD or self.mode not in (Mode.RUN, Mode.TRACK):
            return None
        return -self.ahead.start(motion, params, self._tail_q(), self.planner)

    def ahead_ready(self, descriptor: int) -> bool:
        """The plan started by plan_ahead() is made (submitting the move now costs the motion cycle nothing)."""
        return self.ahead is None or self.ahead.ready(-descriptor)

    def planned_end_q(self) -> np.ndarray:
        """Where the robot will be when every accepted move is done: the start (and IK seed) of the next move."""
        return np.array(self._tail_q())

    def _tail_q(self) -> np.ndarray:
        """Where the robot will be when every accepted move is done: the start of the next one."""
        for h in reversed([*self._in_traj, *self._queue]):
            if h.plan is not None and not h.done:
                return h.plan.end_q
        return self._q_ref.copy()

    # -- stopping, modes, references ---------------------------------------------------

    def stop_move(self, by: str = "stop_move") -> float:
        """Decelerate on the path as fast as the limits allow; returns the s where the move will stop (StopMove)."""
        self._stop_by = by
        traj = self._traj
        for h in self._queue:
            h.stopped_by, h.stopped_s = "cancelled", 0.0
            self._finish(h, MoveStatus.ACT_STOPPED)
        self._queue.clear()
        if traj is None:
            return self._active.s if self._active is not None else 1.0
        row = self._k * self.sub
        if traj.kind in ("short", "timed"):
            lim = self.planner.short_limits(self._q_ref, self._active.params if self._active else DEFAULT_PARAMS)
            new = stop_trajectory(traj.q_f[row], traj.qd_f[row], traj.qdd_f[row], lim, self.dt_s, self.sub, traj)
        elif traj.kind == "brake":
            return float(traj.s[-1])
        else:
            pvc = self.pvc
            new = brake(traj, row, self.kin.arm.qdd_max, None if pvc is None or pvc.in_sync else (pvc.x, pvc.sd))
        stopping = next((h for h in self._in_traj if h.id == int(new.owner[-1])), None)
        for h in self._in_traj:
            h.stopped_by = by if h is stopping else h.stopped_by
            if not h.started:  # a blended successor the brake never reaches
                h.stopped_by, h.stopped_s = "cancelled", 0.0
                self._finish(h, MoveStatus.ACT_STOPPED)
            h.pieces_left = []
        self._set_traj(new, [h for h in self._in_traj if not h.done])
        return float(new.s[-1])

    def set_mode(self, mode: Mode) -> Mode:
        """Change the servo mode; leaving run/track stops the current move on its path first.

        OFF switches the drives off with the brakes engaged (a backend with drives); leaving OFF
        switches them on and holds the arm where the brakes kept it. BLOCK and STANDBY hold the arm at
        standstill with the drives on.
        """
        if mode not in (Mode.RUN, Mode.TRACK) and not self.idle():
            self.stop_move(by=f"mode {mode.value}")
            while not self.idle() and mode is Mode.OFF:  # the brakes close on an arm at standstill
                self.tick()
        set_drives = getattr(self.backend, "set_drives", None)
        if set_drives is not None and (mode is Mode.OFF) != (self.mode is Mode.OFF):
            set_drives(mode is not Mode.OFF)
            if mode is not Mode.OFF:
                self.reset_ref()  # on again: hold where the brakes kept the arm
        self.mode = mode
        return mode

    def get_mode(self) -> Mode:
        return self.mode

    def set_speed_cap(self, tcp_speed_m_s: float | None) -> None:
        """Cap the TCP speed of every move planned from now on (manual mode: 0.25); None removes the cap."""
        if tcp_speed_m_s is not None and not tcp_speed_m_s > 0:
            raise UsageError(f"the TCP speed cap must be positive, got {tcp_speed_m_s}")
        self.planner.tcp_speed_cap_m_s = tcp_speed_m_s

    def reset_ref(self) -> np.ndarray:
        """Take the measured position as the reference (after contact in a search); running moves are cancelled."""
        for h in [*self._in_traj, *self._queue]:
            if not h.done:
                h.stopped_by, h.stopped_s = "reset_ref", h.s
                self._finish(h, MoveStatus.ACT_STOPPED)
        self._queue.clear()
        self._traj, self._in_traj, self._settling, self._hold_cache, self.pvc = None, [], None, None, None
        self._q_ref = np.array(self.backend.q())
        self._qd_ref, self._qdd_ref = np.zeros_like(self._q_ref), np.zeros_like(self._q_ref)
        return self._q_ref.copy()

    def uninstall(self, actions: Actions) -> None:
        """Remove an action set's continuous actions."""
        self._continuous = [(a, h) for a, h in self._continuous if a is not actions]

    # -- waiting ----------------------------------------------------------------------

    def wait(self, what: MoveHandle | MoveSignal, timeout_s: float | None = None) -> bool:
        """Advance time until the move is done (or the semaphore is signalled, consuming it); False on timeout."""
        deadline = None if timeout_s is None else self.now_s() + timeout_s - 1e-12

        def ready() -> bool:
            return what.take() if isinstance(what, MoveSignal) else what.done

        while not ready():
            if deadline is not None and self.now_s() >= deadline:
                return False
            if isinstance(what, MoveSignal) and self.idle() and not any(a.signal is what for a, _ in self._continuous):
                return False  # nothing left that could signal it
            self.tick()
        return True

    def wait_for_room(self, pending: int = 1) -> None:
        """Advance time until at most `pending` moves are unfinished (look-ahead of a zone motion)."""
        while self.pending() > pending:
            self.tick()

    def run_until_idle(self, timeout_s: float | None = None) -> bool:
        """Advance time until every move is done; False on timeout."""
        deadline = None if timeout_s is None else self.now_s() + timeout_s
        while not self.idle():
            if deadline is not None and self.now_s() >= deadline:
                return False
            self.tick()
        return True

    def run_for(self, duration_s: float) -> None:
        """Advance time by (at least) duration_s."""
        end = self.now_s() + duration_s - 1e-12
        while self.now_s() < end:
            self.tick()

    # -- acquire services (thesis 5.2) --------------------------------------------------

    def fk(self, q: np.ndarray, tool: np.ndarray | None = None) -> np.ndarray:
        """Kinematics: the TCP pose (4x4) at q."""
        return self.kin.fk(q, tool)

    def ik(self, pose: np.ndarray, q_seed: np.ndarray | None = None, tool: np.ndarray | None = None) -> np.ndarray:
        """Inverse kinematics: joints for a TCP pose (4x4) near q_seed (default: the current reference)."""
        return self.kin.ik(pose, self._q_ref if q_seed is None else q_seed, tool)

    def dynamics(self, q: np.ndarray, qd: np.ndarray | None = None, qdd: np.ndarray | None = None,
                 load_kg: float = 0.0) -> services.Dynamics:
        """Dynamics at a configuration: torque, mass matrix, gravity."""
        return services.dynamics(self, q, qd, qdd, load_kg)

    def simulate(self, moves: Sequence[Motion | tuple[Motion, Params]], q_start: np.ndarray | None = None) -> services.Simulation:
        """Predicted references and duration of a sequence of moves (blends included), without moving the robot."""
        return services.simulate(self, moves, q_start)

    def path_left(self, what: MoveHandle | Motion, s: float) -> Motion:
        """PathLeft: the rest of a move's path from s, as a motion to request next."""
        return services.path_left(what, s)


def _reowned(plan: Any, owner: int) -> Any:
    """A saved plan handed to a new move: same geometry, the new move's id on every sample."""
    import dataclasses

    pieces = [DensePath(p.q, p.tcp, np.full(len(p.q), owner), p.s) for p in plan.pieces]
    first = plan.saved_first
    if first is not None:
        first = dataclasses.replace(first, owner=np.full(len(first.owner), owner))
        first.path.dense.owner[:] = owner
    return dataclasses.replace(plan, owner=owner, pieces=pieces, saved_first=first)


Callback = Callable[[], None]
