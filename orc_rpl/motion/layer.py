"""The motion layer (thesis 4.3, 5.2): move(), the motion cycle with its actions, blending, stops and modes."""

from __future__ import annotations

import time as wallclock
from collections import deque
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from orc_rpl.errors import OrcError, PlanningError, UsageError
from orc_rpl.motion import services
from orc_rpl.motion.actions import Actions, MotionData, MoveSignal
from orc_rpl.motion.backend import Backend
from orc_rpl.motion.blending import blend
from orc_rpl.motion.braking import brake
from orc_rpl.motion.handle import MoveHandle
from orc_rpl.motion.kinematics import Kinematics
from orc_rpl.motion.paths import DensePath
from orc_rpl.motion.planner import Planner, combine
from orc_rpl.motion.short_move import short_trajectory, stop_trajectory
from orc_rpl.motion.specs import DEFAULT_PARAMS, CartesianMotion, Computation, JointMotion, Mode, Motion, MoveStatus, Params
from orc_rpl.motion.timing import parameterize
from orc_rpl.motion.trajectory import SplinePath, Trajectory

SETTLE_RAD = 2e-5          #: FINE: joint error at which a move counts as arrived
SETTLE_RAD_S = 2e-3        #: FINE: joint speed below which it counts as at rest
SETTLE_TIMEOUT_S = 1.5     #: give up waiting (handle.settled = False) after this long
BLEND_MARGIN_RAD = 0.01    #: a replan starts this far (joint chord) ahead of the reference


class MotionLayer:
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
        self._wall_start: float | None = None
        self.cycles = 0

    # -- reading the robot --------------------------------------------------------------

    def now_s(self) -> float:
        """The controller clock (simulated time on the virtual robot)."""
        return self.backend.time_s()

    def current_q(self) -> np.ndarray:
        """Measured joint positions."""
        return np.array(self.backend.q())

    def reference_q(self) -> np.ndarray:
        """Commanded joint positions."""
        return self._q_ref.copy()

    def tcp_pose(self, tool: np.ndarray | None = None) -> np.ndarray:
        """Measured TCP pose (4x4, world)."""
        return self.kin.fk(self.backend.q(), tool)

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
            plan = self.planner.recall(params.descriptor, motion, q_start)
            h.replanned_during = plan is None
        if plan is None:
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
        self._queue.append(h)
        self._admit()
        return h

    def planned_end_q(self) -> np.ndarray:
        """Where the robot will be when every accepted move is done: the start (and IK seed) of the next move."""
        return np.array(self._tail_q())

    def _tail_q(self) -> np.ndarray:
        """Where the robot will be when every accepted move is done: the start of the next one."""
        for h in reversed([*self._in_traj, *self._queue]):
            if h.plan is not None and not h.done:
                return h.plan.end_q
        return self._q_ref.copy()

    # -- starting and blending --------------------------------------------------------

    def _admit(self) -> None:
        """Start queued moves from rest, or blend the next one into the running trajectory."""
        while self._queue:
            if self._settling is not None:
                return
            if self._traj is None:
                h = self._queue.popleft()
                try:
                    self._start_from_rest(h)
                except OrcError as exc:  # a replan from where the robot really is failed: fault, not a crash
                    self._fault(h, exc)
            elif not self._try_blend(self._queue[0]):
                return
            else:
                self._queue.popleft()

    def _start_from_rest(self, h: MoveHandle) -> None:
        plan = h.plan
        assert plan is not None
        if not np.allclose(plan.start_q, self._q_ref, atol=1e-6, rtol=0.0):
            # the robot is not where the move was planned from (a stop or reset_ref came between): replan
            fresh = self.planner.plan(h.id, h.motion, h.params, self._q_ref)
            if fresh is None:
                self._finish(h, MoveStatus.READY)
                return
            h.plan, h.pieces_left, plan = fresh, list(fresh.pieces), fresh
        piece = h.pieces_left.pop(0)
        if h.short:
            lim = self.planner.short_limits(self._q_ref, h.params)
            traj = short_trajectory(self._q_ref, self._qd_ref * 0, self._qdd_ref * 0, piece.q[-1], lim, self.dt_s,
                                    self.sub, h.id, lambda q: self.kin.fk(q, h.motion.tool)[:3, 3])
        elif plan.timed is not None:
            traj = plan.timed
        elif plan.saved_first is not None and len(h.pieces_left) == len(plan.pieces) - 1:
            traj = plan.saved_first
        else:
            traj = self.planner.time(piece, plan.limits, 0.0, h.params.time_s if len(plan.pieces) == 1 else None)
        self._set_traj(traj, [h])
        if not h.started:
            self._start(h)

    def _set_traj(self, traj: Trajectory, handles: list[MoveHandle]) -> None:
        self._traj, self._k, self._traj_t0 = traj, 0, self.now_s()
        self._in_traj = handles
        owners = traj.owner
        for h in handles:
            idx = np.nonzero(owners == h.id)[0]
            if len(idx):
                h.t_end_s = self._traj_t0 + float(idx[-1]) * self.dt_s

    def _try_blend(self, nxt: MoveHandle) -> bool:
        """Replan from the current state through a blended corner onto `nxt`; False if too late or not a zone move."""
        traj = self._traj
        tail = self._in_traj[-1] if self._in_traj else None
        if (traj is None or not traj.blendable or tail is None or tail.zone_m <= 0 or tail.pieces_left
                or nxt.short or nxt.plan is None or nxt.plan.timed is not None or tail.stopped_by is not None):
            return False
        if not np.allclose(nxt.plan.start_q, tail.plan.end_q, atol=1e-9, rtol=0.0):
            return False
        row = self._k * self.sub
        x_now = float(traj.x_f[row])
        dense = traj.path.dense
        later = np.nonzero(traj.path.x_knots > x_now + BLEND_MARGIN_RAD)[0]
        if len(later) < 3:
            return False
        owner_now, s_now = traj.path.owner_and_s(np.array([x_now]))
        tcp_now = self.kin.tcp_positions(self._q_ref[None, :], tail.motion.tool)
        current = DensePath(np.vstack([self._q_ref, dense.q[later]]), np.vstack([tcp_now, dense.tcp[later]]),
                            np.concatenate([owner_now.astype(int), dense.owner[later]]),
                            np.concatenate([s_now, dense.s[later]]))
        joined = blend(self.kin, current, nxt.pieces_left[0], tail.zone_m, 1, tail.motion.tool,
                       tail.plan.last_chord_rad, nxt.plan.first_chord_rad)
        if joined is None:
            return False
        handles = [h for h in self._in_traj if h.id in set(joined.owner.tolist())] + [nxt]
        limits = combine({h.id: h.plan.limits for h in handles})
        path = SplinePath(joined)
        d1 = path(0.0, 1)
        sd0 = max(0.0, float(self._qd_ref @ d1) / max(float(d1 @ d1), 1e-12))
        try:
            new, _ = parameterize(path, limits, self.dt_s, self.sub, sd0, 0.0)
        except PlanningError:
            return False
        nxt.pieces_left.pop(0)
        tail.blended = True
        self._set_traj(new, handles)
        return True

    # -- the motion cycle ---------------------------------------------------------------

    def tick(self) -> None:
        """One motion cycle: command the next references (sub servo steps), update moves, run actions."""
        traj = self._traj
        if traj is not None and self._k < traj.cycles:
            self._k += 1
            rows = traj.rows(self._k)
            q_r, qd_r, qdd_r = traj.q_f[rows], traj.qd_f[rows], traj.qdd_f[rows]
            self._hold_cache = None
        else:
            if self._hold_cache is None:
                self._hold_cache = (np.tile(self._q_ref, (self.sub, 1)), np.zeros((self.sub, len(self._q_ref))))
            q_r, qd_r = self._hold_cache
            qdd_r = qd_r
        self.backend.advance(q_r, qd_r, qdd_r)
        self._q_ref, self._qd_ref, self._qdd_ref = q_r[-1], qd_r[-1], qdd_r[-1]
        self.cycles += 1
        stop = False
        if traj is not None:
            stop = self._progress(traj)
        if self._settling is not None:
            self._check_settled()
        for acts, h in self._continuous:
            acts.run("continuous", self._data(h, "continuous"))
        if stop and self._traj is not None and self._traj.kind != "brake":
            self.stop_move(by=self._stop_by)
        if self.logger is not None:
            self.logger.update()
        if self.realtime:
            self._pace()

    def _progress(self, traj: Trajectory) -> bool:
        """Hand the cycle's sample to its owning move; start and finish moves; run during actions."""
        owner = int(traj.owner[self._k])
        active = self._active
        if active is None or active.id != owner:
            if active is not None and not active.done and active.id != owner:
                self._finish(active, MoveStatus.READY)
            nxt = next((h for h in self._in_traj if h.id == owner), None)
            if nxt is not None and not nxt.started:
                self._start(nxt)
            active = self._active
        stop = False
        if active is not None:
            active.s = float(traj.s[self._k])
            if active.actions.stage("during"):
                stop = active.actions.run("during", self._data(active, "during"))
                if stop:
                    self._stop_by = next(e.name for e in active.actions.stage("during") if e.slot.stop_requested)
        if self._k >= traj.cycles:
            self._traj_end(traj)
        return stop

    def _traj_end(self, traj: Trajectory) -> None:
        h = self._active
        self._traj = None
        if h is None or h.done:
            self._admit()
            return
        if traj.kind == "brake":
            h.stopped_s = h.s
            self._finish(h, MoveStatus.ACT_STOPPED)
        elif h.pieces_left:
            self._start_from_rest_piece(h)
            return
        elif h.zone_m > 0:
            self._finish(h, MoveStatus.READY)
        else:
            self._settling = (h, self.now_s())
            self._check_settled()
        self._admit()

    def _start_from_rest_piece(self, h: MoveHandle) -> None:
        piece = h.pieces_left.pop(0)
        try:
            self._set_traj(self.planner.time(piece, h.plan.limits), [h])
        except OrcError as exc:
            self._fault(h, exc)

    def _fault(self, h: MoveHandle, exc: OrcError) -> None:
        """A move that cannot go on: status fault with the error; the moves queued after it are cancelled."""
        h.error = exc
        self._finish(h, MoveStatus.FAULT)
        for later in self._queue:
            later.stopped_by, later.stopped_s = "cancelled", 0.0
            self._finish(later, MoveStatus.ACT_STOPPED)
        self._queue.clear()

    def _check_settled(self) -> None:
        h, since = self._settling  # type: ignore[misc]
        err = float(np.max(np.abs(self.backend.q() - self._q_ref)))
        vel = float(np.max(np.abs(self.backend.qd())))
        timed_out = self.now_s() - since > SETTLE_TIMEOUT_S
        if (err < SETTLE_RAD and vel < SETTLE_RAD_S) or timed_out:
            h.settled = not timed_out
            self._settling = None
            self._finish(h, MoveStatus.READY)
            self._admit()

    def _start(self, h: MoveHandle) -> None:
        h.started, h.start_time_s = True, self.now_s()
        self._active = h
        set_payload = getattr(self.backend, "set_control_payload", None)
        if set_payload is not None and h.params.load_kg != self._control_load_kg:
            set_payload(h.params.load_kg)  # thesis 4.5: the load in Par reaches the control, not only the planner
            self._control_load_kg = h.params.load_kg
        if h.actions.stage("pre"):
            h.actions.run("pre", self._data(h, "pre"))
        if h.actions.stage("continuous"):
            self._continuous.append((h.actions, h))

    def _finish(self, h: MoveHandle, status: MoveStatus) -> None:
        if h.done:
            return
        h.status, h.done, h.end_time_s = status, True, self.now_s()
        if status is MoveStatus.READY:
            h.s = 1.0
        if h.started and h.actions.stage("post"):
            h.actions.run("post", self._data(h, "post"))
        h.signal.signal("done", self.now_s())
        if self._active is h:
            self._active = None

    def _data(self, h: MoveHandle, stage: str) -> MotionData:
        q = np.array(self.backend.q())
        q_ref = self._q_ref.copy()
        arrays = [q, np.array(self.backend.qd()), q_ref, self._qd_ref.copy(), np.array(self.backend.torque()), q_ref - q]
        for a in arrays:
            a.setflags(write=False)
        now = self.now_s()
        start = h.start_time_s if h.start_time_s is not None else now
        t_end = h.t_end_s if h.t_end_s is not None else now
        return MotionData(now, now - start, h.s, arrays[0], arrays[1], arrays[2], arrays[3], arrays[4], arrays[5], t_end, stage)

    def _pace(self) -> None:
        if self._wall_start is None:
            self._wall_start = wallclock.perf_counter() - self.now_s()
        ahead = self._wall_start + self.now_s() - wallclock.perf_counter()
        if ahead > 0:
            wallclock.sleep(ahead)

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
            new = brake(traj, row, self.kin.arm.qdd_max)
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
        """Change the servo mode; leaving run/track stops the current move on its path first."""
        if mode not in (Mode.RUN, Mode.TRACK) and not self.idle():
            self.stop_move(by=f"mode {mode.value}")
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
        self._traj, self._in_traj, self._settling, self._hold_cache = None, [], None, None
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
