"""The motion pipeline (thesis 5.2): starting queued moves, blending zone moves, and the motion cycle with its actions."""

from __future__ import annotations

import time as wallclock
from collections import deque
from typing import Any

import numpy as np

from orc_rpl.arm.external import StagedPathVelocityController
from orc_rpl.arm.pvc import PathVelocityController
from orc_rpl.errors import Collision, MotionFault, OrcError, PlanningError
from orc_rpl.motion import scheduling
from orc_rpl.motion.actions import Actions, MotionData
from orc_rpl.motion.backend import Backend
from orc_rpl.motion.blending import blend
from orc_rpl.motion.gear_friction import update_estimates
from orc_rpl.motion.handle import MoveHandle
from orc_rpl.motion.kinematics import Kinematics
from orc_rpl.motion.path_offset import PathOffset, correction_omega_rad_s
from orc_rpl.motion.paths import DensePath
from orc_rpl.motion.planner import Planner, combine
from orc_rpl.motion.short_move import short_trajectory, short_windows
from orc_rpl.motion.specs import MoveStatus
from orc_rpl.motion.timing import parameterize
from orc_rpl.motion.trajectory import SplinePath, Trajectory, smoothed

_NO_SENSORS: dict[str, Any] = {}  #: MotionData.sensors when no sensor is installed (shared, never written)
SETTLE_RAD = 2e-5          #: FINE: joint error at which a move counts as arrived
SETTLE_RAD_S = 2e-3        #: FINE: joint speed below which it counts as at rest
SETTLE_TIMEOUT_S = 1.5     #: give up waiting (handle.settled = False) after this long
BLEND_MARGIN_RAD = 0.01    #: a replan starts this far (joint chord) ahead of the reference


class MotionPipeline:
    """The state and the cycle of the motion layer; `MotionLayer` adds the caller's interface on top."""

    kin: Kinematics
    backend: Backend
    planner: Planner
    dt_s: float
    sub: int
    realtime: bool
    logger: Any
    cycles: int
    _q_ref: np.ndarray
    _qd_ref: np.ndarray
    _qdd_ref: np.ndarray
    _hold_cache: tuple[np.ndarray, ...] | None
    _traj: Trajectory | None
    _k: int
    _traj_t0: float
    _in_traj: list[MoveHandle]
    _queue: deque[MoveHandle]
    _active: MoveHandle | None
    _settling: tuple[MoveHandle, float] | None
    _continuous: list[tuple[Actions, MoveHandle]]
    _stop_by: str
    _t_end_nominal: dict[int, float]
    _control_load_kg: float
    _wall_start: float | None
    thermal: Any
    #: the winding temperature estimate (motion.thermal.WindingTemperature), None when the motors' data is unknown
    winding: Any = None
    #: the gearboxes' warm-up and friction estimate (motion.gear_friction.GearFriction), None when not known
    gear_friction: Any = None
    _tuning: Any
    #: the installed sensors (motion.sensors.SensorManager), read by actions through MotionData.sensors
    sensors: Any = None
    #: the path correction of a tracked move: a joint offset added to the planned references (set_path_offset)
    _track: PathOffset | None = None
    #: path velocity control (thesis 5.3) for moves that do not say (Params.path_velocity None)
    path_velocity_control: bool = False
    #: the path velocity controller of the running trajectory (None: the nominal one is played as planned)
    pvc: PathVelocityController | None = None
    #: the cell's external axes (motion.external.ExternalAxes), None when it has none
    external: Any = None
    _stages: list[Any] = []

    @property
    def smoothing_s(self) -> tuple[float, ...]:
        """Windows (s) over which a path trajectory from rest has its time scaling averaged (elastic gears), () none:
        the planner's (it averages what it times; a trajectory timed elsewhere is averaged when it starts)."""
        return self.planner.smoothing_s

    @smoothing_s.setter
    def smoothing_s(self, windows_s: tuple[float, ...]) -> None:
        self.planner.smoothing_s = tuple(windows_s)

    def now_s(self) -> float:
        """The controller clock (simulated time on the virtual robot)."""
        return self.backend.time_s()

    def stop_move(self, by: str = "stop_move") -> float:  # defined by MotionLayer
        raise NotImplementedError

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
            caps = [c for c in (h.params.speed_m_s if not callable(h.params.speed_m_s) else None,
                                self.planner.tcp_speed_cap_m_s) if c is not None]
            traj = short_trajectory(self._q_ref, self._qd_ref * 0, self._qdd_ref * 0, piece.q[-1], lim, self.dt_s,
                                    self.sub, h.id, lambda q: self.kin.fk(q, h.motion.tool)[:3, 3],
                                    min(caps) if caps else None, short_windows(self.planner.smoothing_s))
        elif plan.timed is not None:
            traj = plan.timed
        elif (plan.saved_first is not None and len(h.pieces_left) == len(plan.pieces) - 1
              and plan.saved_first.smoothing_s in ((), self.planner.smoothing_s)):  # (averaged as this layer wants)
            traj = plan.saved_first
        else:
            traj = self.planner.time(piece, plan.limits, 0.0, h.params.time_s if len(plan.pieces) == 1 else None,
                                     h.params.whole_averaging)
        self._set_traj(traj, [h])
        if not h.started:
            self._start(h)

    def _set_traj(self, traj: Trajectory, handles: list[MoveHandle]) -> None:
        if traj.kind != "brake":
            self._track = None  # a new move starts from the (corrected) reference; a stop keeps the correction
        windows = self.planner.smoothing_s
        if windows and traj.kind == "path" and traj.sd_f[0] == 0.0 and traj.smoothing_s != windows:
            traj = smoothed(traj, windows)  # no torque steps into elastic gears (the planner's own are averaged)
        self._traj, self._k, self._traj_t0 = traj, 0, self.now_s()
        self._in_traj = handles
        owners = traj.owner
        self._t_end_nominal: dict[int, float] = {}
        for h in handles:
            idx = np.nonzero(owners == h.id)[0]
            if len(idx):
                h.t_end_s = self._t_end_nominal[h.id] = self._traj_t0 + float(idx[-1]) * self.dt_s
        self.pvc = self._path_velocity_controller(traj, handles)

    def _path_velocity_controller(self, traj: Trajectory, handles: list[MoveHandle]) -> PathVelocityController | None:
        """A path velocity controller for a trajectory timed along its path, when its first move asks for one."""
        dynamics = getattr(self.backend, "path_dynamics", None)
        self._stages = self.external.stages(traj, handles) if self.external is not None and traj.kind == "path" else []
        wanted = handles[0].params.path_velocity if handles else None
        arm_control = self.path_velocity_control if wanted is None else wanted
        if self._stages:  # external axes in the same path coordinate: the combined range (thesis fig. 5.6)
            return StagedPathVelocityController(traj.path, traj.x_f, traj.sd_f, self.sub, self.backend.servo_period_s,
                                                dynamics if arm_control else None, self.kin.arm.tau_max, self._stages,
                                                path_orders=traj.path.orders)
        if traj.kind != "path" or dynamics is None or not handles:
            return None
        if not arm_control:
            return None
        return PathVelocityController(traj.path, traj.x_f, traj.sd_f, self.sub, self.backend.servo_period_s,
                                      dynamics, self.kin.arm.tau_max,
                                      dynamics_rows=getattr(self.backend, "path_dynamics_rows", None),
                                      path_orders=traj.path.orders)

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
        x_now = self.pvc.x if self.pvc is not None else float(traj.x_f[row])  # where the command really is
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
            whole = any(h.params.whole_averaging for h in handles)   # (from rest only: a blend rarely is)
            new, _ = parameterize(path, limits, self.dt_s, self.sub, sd0, 0.0, smoothing_s=self.planner.smoothing_s,
                                  gear_steps=None if whole else self.planner.gear_steps)
        except PlanningError:
            return False
        nxt.pieces_left.pop(0)
        tail.blended = True
        self._set_traj(new, handles)
        return True

    # -- the motion cycle ---------------------------------------------------------------

    def tick(self) -> None:
        """One motion cycle: command the next references (sub servo steps), update moves, run actions."""
        traj, pvc = self._traj, self.pvc
        if traj is not None and (self._k < traj.cycles if pvc is None else not pvc.done):
            self._k += 1
            scaled = None if pvc is None else pvc.cycle(self._k)
            if scaled is None:
                rows = traj.rows(self._k)
                q_r, qd_r, qdd_r = traj.q_f[rows], traj.qd_f[rows], traj.qdd_f[rows]
            else:
                q_r, qd_r, qdd_r = scaled
                self._rescale_end_times(pvc.lag_s())  # type: ignore[union-attr]
            if self._track is not None:
                dq, dqd, dqdd = self._track.rows(len(q_r), self.dt_s / self.sub)
                q_r, qd_r, qdd_r = q_r + dq, qd_r + dqd, qdd_r + dqdd
            self._hold_cache = None
            if self.external is not None:
                x_end = (pvc.x, pvc.sd) if scaled is not None else (float(traj.x_f[rows][-1]), float(traj.sd_f[rows][-1]))
                self.external.cycle(self.backend, self._stages, x_end[0], x_end[1], self.dt_s)
        else:
            if self._hold_cache is None:
                self._hold_cache = (np.tile(self._q_ref, (self.sub, 1)), np.zeros((self.sub, len(self._q_ref))))
            q_r, qd_r = self._hold_cache
            qdd_r = qd_r
            if self.external is not None:
                self.external.cycle(self.backend, [], None, 0.0, self.dt_s)
        try:
            self.backend.advance(q_r, qd_r, qdd_r)
        except MotionFault as fault:  # a real drive failed (DriveFault): the backend holds, the moves fail
            self._drive_fault(fault)
            return
        collision = getattr(self.backend, "collision", None)
        hit = None if collision is None else collision()
        if hit is not None:
            self._collision_stop(hit)
            traj = None
        if self.thermal is not None:
            gear = self.gear_friction
            update_estimates(self.thermal, self.winding, gear, self.backend.torque(), None if gear is None else self.backend.qd())
        if hit is None:  # a collision stop has set the reference where the robot is
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
        pvc = self.pvc
        if pvc is None or pvc.in_sync and self._k <= traj.cycles:
            owner, s_now = traj.owner.item(self._k), traj.s.item(self._k)  # item(): Python numbers
        else:  # the time scale was changed: the move and its s where the command really is
            owner, s_now = traj.path.owner_and_s_at(pvc.x)
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
            active.s = s_now
            if active.actions and active.actions.stage("during"):
                stop = active.actions.run("during", self._data(active, "during"))
                if stop:
                    self._stop_by = next(e.name for e in active.actions.stage("during") if e.slot.stop_requested)
        if (self._k >= traj.cycles) if pvc is None else pvc.done:
            self._traj_end(traj)
        return stop

    def _collision_stop(self, bodies: tuple[str, str]) -> None:
        """A collision stop: the reference jumps to where the robot is (no braking along the path into the
        obstacle); the running, settling and queued moves fault with Collision naming the two bodies."""
        error = Collision(f"collision between {bodies[0]} and {bodies[1]}: the robot stopped")
        moves = [*self._in_traj, *([self._settling[0]] if self._settling is not None else []), *self._queue]
        self._queue.clear()
        self._traj, self._in_traj, self._settling, self._hold_cache, self.pvc = None, [], None, None, None
        self._q_ref = np.array(self.backend.q())
        self._qd_ref, self._qdd_ref = np.zeros_like(self._q_ref), np.zeros_like(self._q_ref)
        for h in moves:
            if not h.done:
                h.error = error
                self._finish(h, MoveStatus.FAULT)

    def _rescale_end_times(self, lag_s: float) -> None:
        """The moves of a time-scaled trajectory end later by the controller's lag (T_d for actions and blends)."""
        for h in self._in_traj:
            nominal = self._t_end_nominal.get(h.id)
            if nominal is not None and not h.done:
                h.t_end_s = nominal + lag_s

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
            self._set_traj(self.planner.time(piece, h.plan.limits, whole_averaging=h.params.whole_averaging), [h])
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

    def _drive_fault(self, fault: MotionFault) -> None:
        """The drives stopped the arm: every running and queued move fails with the fault, the reference is
        where the arm is. With no move to carry it, the fault goes to the caller at once."""
        handles = [h for h in [*self._in_traj, *self._queue] if not h.done]
        if self._settling is not None:
            handles.append(self._settling[0])
        self._traj, self._in_traj, self._settling, self._hold_cache = None, [], None, None
        self._queue.clear()
        self._q_ref = np.array(self.backend.q())
        self._qd_ref, self._qdd_ref = np.zeros_like(self._q_ref), np.zeros_like(self._q_ref)
        for h in handles:
            if not h.done:
                h.error = fault
                self._finish(h, MoveStatus.FAULT)
        if not handles:
            raise fault

    def _check_settled(self) -> None:
        h, since = self._settling  # type: ignore[misc]
        # maximum.reduce: np.max's own Python wrapper costs more than the reduction (every cycle while settling)
        err = float(np.maximum.reduce(np.abs(self.backend.q() - self._q_ref)))
        vel = float(np.maximum.reduce(np.abs(self.backend.qd())))
        timed_out = self.now_s() - since > SETTLE_TIMEOUT_S
        # a backend may settle coarser than the default: bus servos see whole encoder counts
        settle_rad, settle_rad_s = getattr(self.backend, "settle_rad", SETTLE_RAD), getattr(self.backend, "settle_rad_s", SETTLE_RAD_S)
        if (err < settle_rad and vel < settle_rad_s) or timed_out:
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
        tuning = h.params.tuning
        if tuning is not self._tuning:
            self._set_tuning(tuning)  # thesis 2.4: this motion's own servo tuning
        if h.actions.stage("pre"):
            h.actions.run("pre", self._data(h, "pre"))
        if h.actions.stage("continuous"):
            self._continuous.append((h.actions, h))

    def _finish(self, h: MoveHandle, status: MoveStatus) -> None:
        if h.done:
            return
        h.status, h.done, h.end_time_s = status, True, self.now_s()
        if self._tuning is not None and h.started and h.params.tuning is self._tuning:
            self._set_tuning(None)  # a tuning holds for its motion only (settling included)
        if status is MoveStatus.READY:
            h.s = 1.0
        if h.started and h.actions.stage("post"):
            h.actions.run("post", self._data(h, "post"))
        h.signal.signal("done", self.now_s())
        if self._active is h:
            self._active = None

    def _set_tuning(self, tuning: Any) -> None:
        set_tuning = getattr(self.backend, "set_tuning", None)
        if set_tuning is not None:  # a kinematic follower has no servo to tune
            set_tuning(tuning)
        self._tuning = tuning

    def set_path_offset(self, offset_m: Any, tool: np.ndarray | None = None, smooth: bool = False) -> None:
        """Track mode (thesis 5.2): move the running move's TCP by `offset_m` (world, m) from its planned path,
        from the next motion cycle on (orientation kept: one Jacobian solve); a new move starts without it. With
        `smooth`, where moves from rest are averaged (elastic gears), the offset is reached as a smooth trajectory,
        its speed and acceleration fed forward (motion.path_offset), rather than as a step."""
        if offset_m is None:
            self._track = None
            return
        # the offset is relative to the planned path: the correction the reference carries already is taken off
        planned_q = self._q_ref - self._track.q if self._track is not None else self._q_ref
        jac = self.kin.arm.jacobian(planned_q, tool)
        twist = np.zeros(jac.shape[0])
        twist[:3] = offset_m
        if self._track is None:
            omega = correction_omega_rad_s(sum(self.planner.smoothing_s)) if smooth else None
            self._track = PathOffset(len(planned_q), omega)
        self._track.goal = np.linalg.lstsq(jac, twist, rcond=None)[0]

    def _data(self, h: MoveHandle, stage: str) -> MotionData:
        q = np.array(self.backend.q())
        q_ref = self._q_ref.copy()
        arrays = [q, np.array(self.backend.qd()), q_ref, self._qd_ref.copy(), np.array(self.backend.torque()), q_ref - q]
        for a in arrays:
            a.setflags(write=False)
        now = self.now_s()
        start = h.start_time_s if h.start_time_s is not None else now
        t_end = h.t_end_s if h.t_end_s is not None else now
        sensors = self.sensors.readings.new_cycle(self.cycles) if self.sensors is not None else _NO_SENSORS
        return MotionData(now, now - start, h.s, arrays[0], arrays[1], arrays[2], arrays[3], arrays[4], arrays[5], t_end, stage,
                          sensors)

    def _pace(self) -> None:
        if self._wall_start is None:
            self._wall_start = wallclock.perf_counter() - self.now_s()
            scheduling.request_slice(scheduling.PACED_SLICE_S)  # wake on time while other programs keep the cores busy
        ahead = self._wall_start + self.now_s() - wallclock.perf_counter()
        if ahead > 0:
            wallclock.sleep(ahead)
