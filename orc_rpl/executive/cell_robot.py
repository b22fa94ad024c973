"""The executive's robot on the motion layer: motion requests become MotionLayer.move calls on the virtual cell."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from orc_rpl.application.runtime import FunctionParam, MotionRequest, MotionView, Sample
from orc_rpl.errors import OrcError, PlanningError
from orc_rpl.listeners import Listeners
from orc_rpl.motion import (ActionSlot, Actions, CartesianMotion, Computation, FuncParams, FunctionMotion, JointMotion, Known,
                            MotionData, MotionLayer, MoveStatus, Params)
from orc_rpl.executive.sensor_ahead import correction
from orc_rpl.plant.io import CellIO
from orc_rpl.world.pose import Joints, Pose

#: A servo gripper that has neither arrived nor stalled by then is left where it is (it squeezes a part).
GRIPPER_TIMEOUT_S = 2.0
#: A VIA point of a straight-line motion is passed this close (a blended corner), unless the zone is larger.
VIA_ZONE_M = 0.01


class HandleTicket:
    """A MoveHandle (or the handles of one statement's pieces) as the executive's MoveTicket."""

    def __init__(self, handles: list[Any]) -> None:
        self.handles = handles
        self.signalled_s: float | None = None     #: when t >= T_d - tau first held (request.signal_before_end_s)
        self.recording: list[Sample] = []         #: the first record_s of the motion (request.record_s)

    @property
    def done(self) -> bool:
        return all(h.done for h in self.handles)

    @property
    def outcome(self) -> str:
        if any(h.status is MoveStatus.FAULT for h in self.handles):
            return "fault"
        if any(h.status is MoveStatus.ACT_STOPPED for h in self.handles):
            return "stopped"
        return "reached" if self.done else "running"

    @property
    def error(self) -> Exception | None:
        return next((h.error for h in self.handles if h.error is not None), None)


class CellRobot:
    """RobotInterface over a MotionLayer; IO from the simulated cell (or a plain CellIO with a kinematic backend)."""

    def __init__(self, layer: MotionLayer, io: CellIO | None = None) -> None:
        self.layer = layer
        self.dt_s = layer.dt_s
        loop = getattr(layer.backend, "loop", None)
        self._own_io = io is None and loop is None
        self.io = io if io is not None else loop.cell.io if loop is not None else CellIO()
        self.last_tool: Pose | None = None     #: the tool of the last motion submitted (where a sensor looks)
        self.sensors = _sensor_manager(self)
        layer.sensors = self.sensors
        self.gripper_angles_rad: dict[int, float] = {}  #: servo grippers on the simulated cell (ideal)
        #: the request planned ahead (its plan key), its descriptor, and whether it was computed from sensor dummies
        self._ahead: tuple[MotionRequest, int, bool] | None = None
        self.axes: Any = None  #: the cell's moving frames (executive.cell_axes.CellAxes), after attach_world
        #: who watches the run (the 3D view, the video, the progress display, the margins) listens here, not through
        #: a wrapper in front of every call: called after every motion cycle, and with each motion's ticket once it
        #: is accepted
        self.tick_listeners: Listeners[[]] = Listeners()
        self.submit_listeners: Listeners[[HandleTicket]] = Listeners()

    def attach_world(self, world: Any) -> None:
        """The cell's world model with moving frames: the robot drives its external axes and knows where its base is."""
        from orc_rpl.executive.cell_axes import CellAxes

        self.axes = CellAxes(world, self.layer)

    def axis_values(self) -> dict[str, float]:
        """Where the cell's moving frames are now (m or rad); empty without any."""
        return {} if self.axes is None else self.axes.values()

    @classmethod
    def virtual(cls, robot: str = "irb2400", realtime: bool = False, backend: str = "servo", record: bool = False,
                plant: str = "realistic", seed: int = 0, cell: Any = None) -> CellRobot:
        """The default simulated cell with `robot` (or the cell description `cell`), ready at its home position
        (`plant`: "realistic", "elastic-gears" or "ideal": `robot.plants.SIMULATED_PLANTS`)."""
        from orc_rpl.motion import make_virtual_motion_layer

        return cls(make_virtual_motion_layer(robot=robot, realtime=realtime, backend=backend, record=record,
                                             plant=plant, seed=seed, cell=cell))

    # -- RobotInterface ------------------------------------------------------------------

    @property
    def path_control(self) -> bool:
        """Path velocity control for motions that do not say (`ROBOT.PathControl`)."""
        return self.layer.path_velocity_control

    def set_path_control(self, on: bool) -> None:
        """`ROBOT.PathControl = on`: for the motions requested from now on."""
        self.layer.path_velocity_control = bool(on)

    def time_s(self) -> float:
        return self.layer.now_s()

    def tick(self) -> None:
        self.layer.tick()
        if self._own_io:
            self.io.update(self.layer.now_s())
        self.tick_listeners()

    def pending(self) -> int:
        external = self.layer.external
        return self.layer.pending() + int(external is not None and external.solo is not None)  # axes moving alone

    def stop(self) -> None:
        if not self.layer.idle():
            self.layer.stop_move(by="program")

    def tcp_pose(self, tool: Pose | None) -> Pose:
        tcp = self.layer.tcp_pose(_tool_matrix(tool))
        if self.axes is not None:  # the track carries the base: the program's world is not the base frame
            tcp = self.axes.base(self.axes.values()) @ tcp
        return Pose.from_matrix(tcp)

    def joints(self) -> tuple[float, ...]:
        return tuple(float(q) for q in self.layer.current_q())

    def torques(self) -> tuple[float, ...]:
        return tuple(float(t) for t in self.layer.backend.torque())

    def position_error_m(self) -> float:
        layer = self.layer
        return float(np.linalg.norm(layer.fk(layer.reference_q())[:3, 3] - layer.fk(layer.current_q())[:3, 3]))

    def thermal_loads(self) -> tuple[float, ...]:
        return tuple(float(x) for x in self.layer.thermal_load())

    def drive_gripper(self, servo_id: int, angle_rad: float, current_limit_a: float) -> bool:
        """A gripper on a servo of the arm's bus: move it and wait until it is there (or squeezes at its current limit).

        True when it stopped on an object, squeezing it (a grip). A backend without gripper servos (the
        ideal plant) has an ideal gripper: it is where it was sent at once, and holds nothing."""
        backend = self.layer.backend
        drive = getattr(backend, "drive_servo", None)
        if drive is None:
            self.gripper_angles_rad[servo_id] = angle_rad
            return False
        drive(servo_id, angle_rad, current_limit_a)
        deadline = self.layer.now_s() + GRIPPER_TIMEOUT_S
        while not backend.servo_arrived(servo_id) and self.layer.now_s() < deadline:
            self.tick()
        return bool(backend.servo_holding(servo_id))

    def plant_tcp_pose(self, tool: Pose | None) -> Pose:
        """Simulation only: where the plant's tool really is, which the cell's process models (a weld gun, a laser
        on its seam, a casting's contact) see: the links' own angles, through elastic gears too (the controller's
        `tcp_pose` is its estimate: the encoders less the twist it commands). Through rigid gears, and on a robot
        without a simulated plant of ours, it is tcp_pose: the encoders tell the links' angles there to a count."""
        cell = getattr(getattr(self.layer.backend, "loop", None), "cell", None)
        if not getattr(cell, "elastic", False):
            return self.tcp_pose(tool)
        tcp = self.layer.kin.fk(np.asarray(cell.link_q), _tool_matrix(tool))
        if self.axes is not None:
            tcp = self.axes.base(self.axes.values()) @ tcp
        return Pose.from_matrix(tcp)

    def set_plant_payload(self, mass_kg: float) -> None:
        """Simulation only: a part of `mass_kg` in the gripper, felt by the plant (not told to the controller)."""
        loop = getattr(self.layer.backend, "loop", None)
        cell = getattr(loop, "cell", None)
        if cell is not None:
            cell.set_payload(mass_kg)

    def push_on_arm(self, force_n: Any, point_m: Any) -> None:
        """Simulation only: an external force (world, N) on the arm at a world point (a casting's contact)."""
        cell = getattr(getattr(self.layer.backend, "loop", None), "cell", None)
        if cell is not None:
            cell.push(force_n, point_m)

    def joint_speeds(self) -> tuple[float, ...]:
        """Measured joint speeds (rad/s)."""
        return tuple(float(v) for v in self.layer.backend.qd())

    def _servo(self) -> Any:
        """Our joint servo under the motion layer, or None (a kinematic robot, bus servos)."""
        return getattr(getattr(self.layer.backend, "loop", None), "servo", None)

    def model_torques(self, q: tuple[float, ...], qd: tuple[float, ...]) -> tuple[float, ...]:
        """The controller's own model of the torques for a steady motion state (qdd = 0): rigid-body dynamics with
        the declared payload plus the NOMINAL joint friction (not the plant's), what the servo feeds forward."""
        servo = self._servo()
        q_a, qd_a = np.array(q, dtype=float), np.array(qd, dtype=float)
        if servo is not None:
            return tuple(float(t) for t in servo.model_torque(q_a, qd_a, np.zeros_like(q_a)))
        return tuple(float(t) for t in self.layer.dynamics(q_a, qd_a, np.zeros_like(q_a), 0.0).torque_nm)

    def friction_state(self) -> Any:
        """The controller's estimate of the joint friction now (motion.gear_friction.FrictionState), None without one."""
        gears = getattr(self.layer, "gear_friction", None)
        return None if gears is None else gears.state(self.time_s())

    def jacobian_linear(self, tool: Pose | None) -> np.ndarray:
        """d(TCP position)/dq (3 x n, world) at the measured joint angles."""
        return np.asarray(self.layer.kin.arm.jacobian(self.layer.current_q(), _tool_matrix(tool)))[:3]

    def start_averaging_s(self) -> float:
        """How long the motion layer averages a move's start from rest over the gears' periods (s; 0: not averaged,
        rigid gears): a move from rest reaches its accelerations that much later (docs/robots.md, elastic gears)."""
        return float(sum(getattr(self.layer, "smoothing_s", ()) or ()))

    def servo_gains(self) -> Any:
        """The joint servo's default gains (`ServoGains`: per-joint caps and the elastic gears they were placed
        for), or None on a robot without a servo of ours (kinematic, bus servos)."""
        servo = self._servo()
        return None if servo is None else servo.gains

    def servo_friction(self) -> Any:
        """The joint friction the servo's model feeds forward (Coulomb N m, viscous N m s/rad per joint), or None."""
        servo = self._servo()
        return None if servo is None else servo.friction()

    def inverse_dynamics(self, q: tuple[float, ...], qd: tuple[float, ...], qdd: tuple[float, ...],
                         load_kg: float) -> tuple[float, ...]:
        return tuple(float(t) for t in self.layer.dynamics(np.array(q), np.array(qd), np.array(qdd), load_kg).torque_nm)

    def plan_ahead(self, request: MotionRequest, from_dummy: bool = False) -> bool:
        """Start planning `request` on the motion layer's worker, to follow the moves accepted so far (thesis 5.2,
        computation save); submit() uses the plan when it is given the same request and the robot is where the plan
        starts. False when the request is not planned ahead (partly or not known, a FUNC in it, several pieces).
        `from_dummy`: the request was computed with the sensors' dummy values; submit() then also uses the plan for
        a request whose target the real sensor moved a little (executive/sensor_ahead.py)."""
        if self.axes is not None:  # a cell with moving frames re-bases targets where the track will be: planned then
            return False
        params = _params(request)
        motion = self._single_motion(request)
        if motion is None or type(params) is not Params:  # a FUNC of s runs the program's code: never on the worker
            return False
        descriptor = self.layer.plan_ahead(motion, params)
        if descriptor is None:
            return False
        self._ahead = (_plan_key(request), descriptor, from_dummy)
        if from_dummy:
            self.layer.ahead.counts.from_dummy += 1  # type: ignore[union-attr]
        return True

    def ahead_ready(self) -> bool:
        """The plan started by plan_ahead() is made (or none is being made)."""
        return self._ahead is None or self.layer.ahead_ready(self._ahead[1])

    @property
    def planning(self) -> Any:
        """What planning ahead achieved (`motion.ahead.Counts`), or None without a worker."""
        return None if self.layer.ahead is None else self.layer.ahead.counts

    def _single_motion(self, request: MotionRequest) -> Any:
        """The one motion-layer motion of a request planned ahead: to a single target, nothing computed at run time."""
        if request.short or request.via or request.known in ("partly", "not") or request.kind not in ("joint", "linear"):
            return None
        tool = _tool_matrix(request.tool)
        if type(request.target) is Pose:
            return CartesianMotion(target=request.target, kind=request.kind, tool=tool)  # type: ignore[arg-type]
        if type(request.target) is Joints and request.kind == "joint":
            return JointMotion(target_rad=tuple(request.target.values), tool=tool)
        return None

    def submit(self, request: MotionRequest) -> HandleTicket:
        """Plan and start the request's move(s); planning errors (Unreachable, JointLimit...) are raised here."""
        tool = _tool_matrix(request.tool)
        self.last_tool = request.tool
        params = _params(request)
        ahead, self._ahead = self._ahead, None
        if ahead is not None and ahead[0] == _plan_key(request):  # the program's knowledge proved right (done)
            params = dataclasses.replace(params, computation=Computation.DONE, descriptor=ahead[1])
            if ahead[2]:
                self.layer.ahead.counts.confirmed += 1  # type: ignore[union-attr]
        elif ahead is not None and ahead[2]:  # planned from the dummies: the real sensor's answer corrects it
            fix = correction(ahead[0], request)
            if fix is not None:
                request = dataclasses.replace(request, target=ahead[0].target, correction=fix.along())
                self.layer.ahead.counts.corrected += 1  # type: ignore[union-attr]
            # the layer uses the plan if the motion is the one planned, else plans it again (replanned)
            params = dataclasses.replace(_params(request), computation=Computation.DONE, descriptor=ahead[1])
        actions = _until_actions(request)
        layer = self.layer
        handles = []
        ticket = HandleTicket(handles)
        if request.signal_before_end_s is not None or request.record_s > 0:
            actions = _application_actions(request, ticket, actions)
        if request.correction is not None:
            actions = _correction_action(request, layer, tool, actions)
        if self.axes is not None and (request.axes or request.frame_of is not None):
            handles.append(self.axes.submit(request, tool, params, actions))
            request = None  # type: ignore[assignment]
        elif self.axes is not None:  # targets in the program's world, in the base frame where the track will be
            planned = self.axes.planned()
            request = dataclasses.replace(request, target=_based(self.axes, request.target, planned),
                                          via=tuple(_based(self.axes, p, planned) for p in request.via))
        if request is None:
            pass
        elif request.known == "not" and type(request.target) is Pose and request.kind in ("joint", "linear") \
                and not request.via:
            # not known: no path or time-optimal planning in advance; a jerk-limited trajectory generated from where
            # the robot is when it starts (thesis 5.2: run-time trajectory generation)
            motion = CartesianMotion(target=request.target, kind=request.kind, tool=tool)  # type: ignore[arg-type]
            handles.append(layer.short_move(motion, _params(request, zone_m=0.0), actions))
        elif request.short and request.kind in ("joint", "linear") and not request.via and request.until is None \
                and type(request.target) is Pose:
            # ShortMove: jerk- and acceleration-limited, dynamics taken as constant, always FINE
            motion = CartesianMotion(target=request.target, kind=request.kind, tool=tool)  # type: ignore[arg-type]
            handles.append(layer.short_move(motion, _params(request, zone_m=0.0), actions))
        elif request.kind == "linear":  # a straight line (through its VIA points, blended)
            corner = _params(request, zone_m=max(request.zone_m, VIA_ZONE_M))
            for point in request.via:  # the path correction (GRINDMOVE's force loop) holds on every segment
                segment = _until_actions(request)
                if request.correction is not None:
                    segment = _correction_action(request, layer, tool, segment)
                handles.append(layer.move(_motion(layer, point, "linear", None, tool), corner, segment))
            handles.append(layer.move(_motion(layer, request.target, "linear", None, tool), params, actions))
        elif request.kind == "function":
            handles.append(layer.move(_function_motion(request.target, tool, request.time_s), params, actions))  # type: ignore[arg-type]
        elif request.kind == "circular":
            handles.append(layer.move(_motion(layer, request.target, "circular", request.via[0], tool), params, actions))
        else:
            handles.append(layer.move(_joint_motion(layer, request, tool), params, actions))
        for h in handles:
            if h.status is MoveStatus.FAULT and h.error is not None:
                raise h.error
            if h.status is MoveStatus.ILLEGAL:
                raise PlanningError(f"the motion layer refused the move (mode {layer.get_mode().value})")
        self.submit_listeners(ticket)
        return ticket


def _based(axes: Any, point: Any, values: dict[str, float]) -> Any:
    """A world pose in the base frame where the axes will be; joints and functions as they are."""
    return axes.in_base(point, values) if type(point) is Pose else point


def _sensor_manager(robot: Any) -> Any:
    """The robot's sensors, simulated from the cell's process models (the seam) at the last tool's TCP."""
    from orc_rpl.executive.sim_io import simulated_sensors
    from orc_rpl.motion.sensors import SensorManager

    def tcp() -> tuple[float, float, float]:
        pose = robot.plant_tcp_pose(robot.last_tool)
        return (pose.x, pose.y, pose.z)
    return SensorManager(simulated_sensors(robot.io, tcp))


def _correction_action(request: MotionRequest, layer: MotionLayer, tool: np.ndarray | None,
                       actions: Actions | None) -> Actions:
    """Path correction at the motion rate (TRACKMOVE): the request's correction gives the TCP offset from the
    planned path each cycle (applied from the next one), or None to stop on the path."""
    acts = actions if actions is not None else Actions()
    correction = request.correction

    def correct(data: MotionData, slot: ActionSlot) -> None:
        if slot.stop_requested:
            return
        offset = correction(MotionView(data.time_s, data.s, data.sensors))  # type: ignore[misc]
        if offset is None:
            slot.signal(data.s)
            slot.request_stop()
        else:
            layer.set_path_offset(np.asarray(offset, dtype=float), tool, smooth=request.smooth_correction)
    acts.add("during", correct, "correction")
    return acts


def _plan_key(request: MotionRequest) -> MotionRequest:
    """What a plan depends on: the request without its run-time closures (UNTIL, correction), made anew each time."""
    return dataclasses.replace(request, until=None, correction=None)


def _tool_matrix(tool: Pose | None) -> np.ndarray | None:
    if tool is None or (tool.x, tool.y, tool.z, tool.a, tool.b, tool.c) == (0.0, 0.0, 0.0, 0.0, 0.0, 0.0):
        return None
    return tool.matrix()


def _params(request: MotionRequest, zone_m: float | None = None) -> Params:
    varying = callable(request.speed_m_s) or callable(request.speed_fraction)
    kind = FuncParams if varying else Params
    try:
        return kind(speed_m_s=request.speed_m_s, speed_fraction=request.speed_fraction,
                    accel_fraction=request.accel_fraction, zone_m=request.zone_m if zone_m is None else zone_m,
                    time_s=request.time_s, load_kg=request.load_kg,
                    tuning=request.tuning, path_velocity=request.path_control, known=Known(request.known),
                    whole_averaging=request.whole_averaging)
    except OrcError as error:
        raise PlanningError(f"{request.keyword}: {error}") from None


def _until_actions(request: MotionRequest) -> Actions | None:
    """UNTIL as a during-action: the compiled condition is called every motion cycle."""
    until = request.until
    if until is None:
        return None
    from orc_rpl.motion import until as until_action

    def condition(data: MotionData) -> bool:
        return bool(until(MotionView(data.time_s, data.s)))
    return until_action(condition, name="until")


def _application_actions(request: MotionRequest, ticket: HandleTicket, actions: Actions | None) -> Actions:
    """The application layer's actions on a move: signal at t >= T_d - tau (spot welding), record the first
    record_s of torques, q and q-dot (identification); results go to the ticket."""
    acts = actions if actions is not None else Actions()
    tau = request.signal_before_end_s
    if tau is not None:
        def before_end(data: MotionData, slot: ActionSlot) -> None:
            if slot.signalled_at_s is None and data.time_s >= data.t_end_s - tau - 1e-9:
                slot.signal(data.time_s)
                ticket.signalled_s = data.time_s
        acts.add("during", before_end, "before_end")
        # a move shorter than tau (or one that ends early) still signals, at its end at the latest
        def at_end(data: MotionData, slot: ActionSlot) -> None:
            if ticket.signalled_s is None:
                ticket.signalled_s = data.time_s
        acts.add("post", at_end, "before_end_post")
    if request.record_s > 0:
        duration = request.record_s

        def record(data: MotionData, slot: ActionSlot) -> None:
            if data.t_motion_s <= duration + 1e-9:
                ticket.recording.append(Sample(data.time_s, tuple(data.q.tolist()), tuple(data.qd.tolist()),
                                               tuple(data.torque.tolist())))
        acts.add("during", record, "record")
    return acts


def _motion(layer: MotionLayer, point: Pose | Joints, kind: str, via: Pose | Joints | None, tool: np.ndarray | None) -> Any:
    if type(point) is Joints:
        point = Pose.from_matrix(layer.fk(np.array(point.values), tool))
    if via is not None and type(via) is Joints:
        via = Pose.from_matrix(layer.fk(np.array(via.values), tool))
    return CartesianMotion(target=point, kind=kind, via=via, tool=tool)  # type: ignore[arg-type]


def _function_motion(target: FunctionParam, tool: np.ndarray | None, duration_s: float | None = None) -> FunctionMotion:
    """A FUNC of s (or of t, lasting `duration_s`) giving world poses as the motion layer's FunctionMotion (one call of
    the FUNC per sample)."""
    memo: dict[float, Pose] = {}

    def component(name: str) -> Any:
        def at(s: float) -> float:
            if s not in memo:
                memo.clear()
                memo[s] = target.fn(s)
            return getattr(memo[s], name)
        return at

    if target.variable == "t":
        return FunctionMotion(*(component(c) for c in "xyzabc"), variable="t", duration_s=duration_s or 0.0, tool=tool)
    return FunctionMotion(*(component(c) for c in "xyzabc"), tool=tool)


def _joint_motion(layer: MotionLayer, request: MotionRequest, tool: np.ndarray | None) -> Any:
    """MOVE: to a pose (inverse kinematics near the start) or to joints, through its VIA points."""
    if type(request.target) is Pose and not request.via:
        return CartesianMotion(target=request.target, kind="joint", tool=tool)
    seed = layer.planned_end_q()  # where the robot will be when the queued moves are done
    via_rad = []
    for point in request.via:
        seed = np.array(point.values) if type(point) is Joints else layer.ik(point.matrix(), seed, tool)
        via_rad.append(tuple(seed))
    target = request.target
    q = np.array(target.values) if type(target) is Joints else layer.ik(target.matrix(), seed, tool)
    return JointMotion(target_rad=tuple(q), via_rad=tuple(via_rad), tool=tool)
