"""The virtual robot: a motion layer wired to the arm model, the servo loop and the MuJoCo cell (or a kinematic follower)."""

from __future__ import annotations

from typing import Any

import numpy as np

from orc_rpl.errors import UsageError
from orc_rpl.motion.ahead import PlanAhead
from orc_rpl.motion.backend import KinematicBackend
from orc_rpl.motion.kinematics import Kinematics
from orc_rpl.motion.layer import MotionLayer
from orc_rpl.motion.planner import Planner
from orc_rpl.motion.gear_friction import GearFriction
from orc_rpl.motion.gear_steps import GearSteps
from orc_rpl.motion.thermal import WindingTemperature
from orc_rpl.motion.timing import preload as preload_planning
from orc_rpl.robot.plants import SIMULATED_PLANTS, check_elastic_gears
from orc_rpl.robot.servo_plants import servo_plant_spec


class ServoBackend:
    """The servo loop and plant below the motion layer (`orc_rpl.servo.ServoLoop`) as a motion Backend."""

    def __init__(self, loop: Any) -> None:
        self.loop = loop
        self.servo_period_s = float(loop.period_s)
        self._state = loop.state()
        # the servo's own model (its payload is the control payload), as a bare RNEA
        self._rnea = loop.servo.arm.inverse_dynamics_function()
        if not loop.cell.description.contacts:
            self.collision = None  # type: ignore[assignment]  # nothing can collide: the cycle need not ask
        self._zero = np.zeros(loop.servo.arm.n_joints)

    def advance(self, q_ref: np.ndarray, qd_ref: np.ndarray, qdd_ref: np.ndarray) -> None:
        self._state = self.loop.run(q_ref, qd_ref, qdd_ref, len(q_ref))

    def q(self) -> np.ndarray:
        return self._state.q

    def qd(self) -> np.ndarray:
        return self._state.qd

    def torque(self) -> np.ndarray:
        return self._state.tau

    def position_error(self) -> np.ndarray:
        return self._state.position_error

    def time_s(self) -> float:
        return self._state.time_s

    def reset(self, q: np.ndarray) -> None:
        self._state = self.loop.reset(q)

    def set_tuning(self, tuning: Any) -> None:
        """The servo tuning of the motion now starting (a `ServoTuning`, or None for the default gains)."""
        self.loop.set_tuning(tuning)

    def path_dynamics(self, q: np.ndarray, d1: np.ndarray, d2: np.ndarray, sd: float) -> tuple[np.ndarray, np.ndarray]:
        """The arm controller along a path as tau = b1 s'' + b2 (thesis 5.3), for the path velocity controller.

        q, d1, d2: the path and its derivatives by s at one point, sd = ds/dt. b2 includes the servo's
        integral torque: what the model does not know (an undeclared payload, friction) as the servo sees it.
        """
        servo, rnea, zero = self.loop.servo, self._rnea, self._zero
        b2 = servo.model_torque(q, d1 * sd, d2 * (sd * sd))
        b2 += servo.integral
        b1 = rnea(q, zero, d1)
        b1 -= rnea(q, zero, zero)  # M(q) d1: friction has no part in it
        return b1, b2

    def path_dynamics_rows(self, q: np.ndarray, d1: np.ndarray, d2: np.ndarray, sd: np.ndarray) -> PathDynamicsBlocks:
        """`path_dynamics` at k points of a path given as rows (the nominal trajectory's motion-cycle rows): a
        callable giving row i's (b1, b2), its model part computed in batches (see `PathDynamicsBlocks`)."""
        return PathDynamicsBlocks(self.loop.servo, q, d1, d2, sd)

    def collision(self) -> tuple[str, str] | None:
        """The two bodies of a collision in the cell since the last call (then forgotten), or None."""
        cell = self.loop.cell
        hit = cell.collision
        if hit is not None:
            cell.clear_collision()
        return hit

    def set_drives(self, on: bool) -> None:
        """Drives on, or off with the brakes engaged (the OFF mode)."""
        self.loop.set_drives(on)
        self._state = self.loop.state()

    def drive_axes(self, references: dict[str, tuple[float, float, float]], period_s: float) -> None:
        """The external axes' references (position, speed, acceleration) at the end of the next motion cycle;
        none: the drives hold where they are."""
        axes = getattr(self.loop.cell, "axes", None)
        if axes is None:
            return
        if not references:
            axes.hold()
            return
        axes.command({name: axes.axes[name].command(*ref) for name, ref in references.items()}, period_s)

    def axis_values(self) -> dict[str, float]:
        """Where the external axes are (m or rad), measured; empty when the cell has none."""
        axes = getattr(self.loop.cell, "axes", None)
        return {} if axes is None else axes.values()

    def set_control_payload(self, mass_kg: float) -> None:
        """The payload the servo's feed-forward assumes (a move's LOAD); the plant's real payload is not touched."""
        self.loop.servo.set_control_payload(mass_kg)  # the servo's own model (loop.arm is another copy)


#: Rows of a path whose model torques `PathDynamicsBlocks` computes at once (0.4 s of 4 ms motion cycles).
ROWS_BLOCK = 100


class PathDynamicsBlocks:
    """The servo's tau = b1 s'' + b2 along a path at given rows, as `ServoBackend.path_dynamics` gives them, cheaper.

    The thesis' formulation along a planned path: b1 = m(s) = M(q) q'(s), and b2 = c(s) s'^2 + g(s) +
    friction(q'(s) s') + the servo's integral, the model part computed for ROWS_BLOCK rows at once with
    the batched RNEA when a row of a new block is first asked for (again if the control payload changes;
    a change of the friction, every 0.1 s with the gearboxes' estimate, makes only the friction term again),
    the integral added at each call: the same numbers as `path_dynamics`, row by row.
    A term of a more detailed drive model (an elastic gear's twist, say) would be added per row here, as
    in `path_dynamics`.
    """

    def __init__(self, servo: Any, q: np.ndarray, d1: np.ndarray, d2: np.ndarray, sd: np.ndarray) -> None:
        self._servo = servo
        self._q, self._d1 = q, d1
        self._qd, self._qdd = d1 * sd[:, None], d2 * (sd * sd)[:, None]
        self._rnea_rows = servo.arm.inverse_dynamics_rows_function()
        self._start = self._stop = 0
        self._payload: Any = None
        self._coulomb: Any = None
        self._b1 = self._b2 = self._rigid = np.zeros((0, q.shape[1]))

    def __call__(self, i: int) -> tuple[np.ndarray, np.ndarray]:
        """(b1, b2) at row i (b1 a view of the block: read, do not write)."""
        b1, b2, integral = self.parts(i)
        return b1, b2 + integral

    def parts(self, i: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(b1, b2 without the servo's integral, the integral) at row i: b2 is their sum (views: read, do not write;
        the path velocity controller adds them inside its compiled range, without an array for the sum)."""
        servo = self._servo
        # the payload's tuple and the friction's arrays are new objects when they change
        if not self._start <= i < self._stop or self._payload is not servo.arm.payload:
            self._block(i)
        elif self._coulomb is not servo._coulomb:
            self._friction()
        i -= self._start
        return self._b1[i], self._b2[i], servo.integral

    def _block(self, start: int) -> None:
        """The model's b1 and b2 (without the integral) at rows start .. start + ROWS_BLOCK."""
        servo, rows = self._servo, slice(start, start + ROWS_BLOCK)
        q, d1 = self._q[rows], self._d1[rows]
        self._rigid, self._b1 = np.empty(q.shape), np.empty(q.shape)
        self._rnea_rows(q, self._qd[rows], self._qdd[rows], self._rigid)   # the servo's model torque, rigid part
        zero, gravity = np.zeros(q.shape), np.empty(q.shape)
        self._rnea_rows(q, zero, d1, self._b1)
        self._rnea_rows(q, zero, zero, gravity)
        self._b1 -= gravity  # M(q) d1: friction has no part in it
        self._start, self._stop = start, start + len(q)
        self._payload = servo.arm.payload
        self._friction()

    def _friction(self) -> None:
        """b2 of the block from its rigid-body part and the servo's friction now (`JointServo.model_torque`'s sum)."""
        servo = self._servo
        friction = servo.model_friction(self._qd[self._start : self._stop])
        self._b2 = self._rigid if friction is None else self._rigid + friction
        self._coulomb = servo._coulomb


#: The virtual robots (docs/robots.md, "Which plant"): "realistic" is not the controller's model (rigid gears),
#: "elastic-gears" is the realistic plant with elastic gears under the state feedback, "ideal" is the model's twin.
PLANTS = SIMULATED_PLANTS


def _make_cell(robot: str, plant: str, seed: int, cell: Any = None, elastic: bool = False) -> Any:
    """The MuJoCo cell of a virtual robot (the default cell, or the description `cell`); `elastic`: elastic gears."""
    if plant == "ideal":
        from orc_rpl.plant.sim import SimCell

        return SimCell(None if cell is not None else robot, cell)
    from orc_rpl.plant.realistic import RealisticCell

    return RealisticCell(None if cell is not None else robot, cell, seed=seed, elastic=elastic)


def make_virtual_motion_layer(
    robot: str = "irb2400",
    motion_period_s: float = 0.004,
    realtime: bool = False,
    logger: Any = None,
    backend: str = "servo",
    q0: np.ndarray | None = None,
    record: bool = False,
    plant: str = "realistic",
    seed: int = 0,
    cell: Any = None,
    elastic: bool = False,
    gear_feedforward: bool = False,
    gear_observer: bool = False,
    state_feedback: bool = False,
    scaled_averaging: bool | None = None,
) -> MotionLayer:
    """A motion layer on the virtual robot.

    backend "servo": ServoLoop + MuJoCo cell (1 ms steps); "kinematic": the reference is followed
    perfectly (fast; no plant). `plant` "realistic" (friction, hot motors, encoders, masses off the
    model's; deterministic for `seed`), "elastic-gears" (the realistic plant with elastic gears, the gears'
    feed-forward and the state feedback: `elastic`, `gear_feedforward` and `state_feedback` all on; robots
    with a gear stiffness only) or "ideal" (the controller's own model, exactly). `record=True`
    makes a signals Logger with q_ref, q, qd_ref, tau, tcp and s (available as `layer.logger`); pass
    your own `logger` to choose the signals yourself. `cell` (a `plant.CellDescription`, e.g. made from
    a world model by `plant.world_scene.cell_from_world`) replaces the default cell. `elastic`: the
    realistic plant's elastic gears (robots with a gear stiffness), the servo tuned for them
    (servo/two_mass.py); with `gear_feedforward` also the rotors leading the links by the gears'
    twist (the model's torque plus the servo's averaged integral), trajectories from rest averaged
    over the gears' anti-resonance periods, the position loops at TWIST_POSITION_OVER_VELOCITY of
    the velocity loops, and the servo's friction feed-forward following the controller's gearbox
    estimate (`layer.gear_friction`: cold-start friction, falling as the gearboxes warm; docs/robots.md,
    "Elastic gears"); `gear_observer` (opt-in on top) takes the torque the model lacks in the twist from a
    gear-torque observer (servo/gear_observer.py) instead of the servo's averaged integral;
    `state_feedback` (opt-in on top, instead of the observer) controls the slow joints by state feedback
    designed for the two-mass joints (servo/state_feedback.py: an LQR on the rotors' and the links' states,
    a Kalman filter every 1 ms step, the unknown torques its integral action), the wrist by the cascade;
    `scaled_averaging` (under the state feedback; None: on for `plant="elastic-gears"`, off for the keywords)
    averages each move from rest over only as much of the periods as its steps twist the gears
    (motion/gear_steps.py; a motion asking for `Params.whole_averaging`, IDENTMOVE's lift and TRACKMOVE, keeps
    the whole periods); `scaled_averaging=False` averages every move over the whole periods (docs/motion.md,
    "Averaging on elastic gears").
    """
    if plant not in PLANTS:
        raise UsageError(f"plant must be one of {', '.join(PLANTS)}, not {plant!r}")
    if scaled_averaging is None:   # nearer time-optimal, every application's figure within its target (docs/motion.md)
        scaled_averaging = plant == "elastic-gears"
    if plant == "elastic-gears":   # the realistic plant with the elastic gears' whole servo
        check_elastic_gears(robot, "plant='elastic-gears'")
        plant, elastic, gear_feedforward, state_feedback = "realistic", True, True, True
    if elastic and plant != "realistic":
        raise UsageError(f"elastic gears are part of the realistic plant, not of the {plant} one")
    if gear_feedforward and not elastic:
        raise UsageError("gear_feedforward is for elastic gears (elastic=True)")
    if scaled_averaging and not state_feedback:
        raise UsageError("scaled_averaging is for the elastic gears' state feedback (state_feedback=True)")
    if state_feedback and not gear_feedforward:
        raise UsageError("state_feedback is a part of the gears' feed-forward (gear_feedforward=True)")
    if gear_observer and not gear_feedforward:
        raise UsageError("gear_observer is a part of the gears' feed-forward (gear_feedforward=True)")
    from orc_rpl.robot import load_robot, solve_ik

    arm = load_robot(robot)
    kin = Kinematics(arm, solve_ik)
    start = np.array(arm.home_q if q0 is None else q0, dtype=float)
    kin.check_limits(start, "start position")
    servo_arm = backend == "servo" and plant == "realistic" and servo_plant_spec(robot) is not None
    if elastic and servo_arm:
        raise UsageError(f"robot {robot!r} runs on bus servos: its plant has no elastic gears")
    smoothing: tuple[float, ...] = ()   #: elastic gears: the windows trajectories are averaged over
    gear_steps: GearSteps | None = None   #: elastic gears under state feedback: the windows scaled to each trajectory
    if servo_arm:
        # an arm on bus servos: its position loops are the servos' own; goals are streamed to them
        from orc_rpl.motion.servo_arm import ServoArmBackend
        from orc_rpl.plant.servo_arm import ServoArmCell

        be: Any = ServoArmBackend(ServoArmCell(None if cell is not None else robot, cell), motion_period_s)
        be.reset(start)
    elif backend == "servo":
        from orc_rpl.servo.control import ServoGains
        from orc_rpl.servo.loop import ServoLoop

        # The servo gets its own model: a payload is state of an ArmModel, and the planner's
        # what-if torque computations must not change the servo's feed-forward.
        sim = _make_cell(robot, plant, seed, cell, elastic)
        gains = ServoGains()
        if getattr(sim, "elastic", False):
            from orc_rpl.servo.two_mass import POSITION_OVER_VELOCITY, TWIST_POSITION_OVER_VELOCITY, two_mass_gains

            share = TWIST_POSITION_OVER_VELOCITY if gear_feedforward else POSITION_OVER_VELOCITY
            gains = two_mass_gains(arm, sim.motor_inertia_kg_m2, sim.plant.gear_stiffness_nm_rad,
                                   position_over_velocity=share)
        loop = ServoLoop(load_robot(robot), sim, gains)
        if plant == "realistic":
            from orc_rpl.robot.plants import COPPER_TEMPCO_1_K, plant_spec

            nominal = plant_spec(robot)
            loop.servo.set_friction(nominal.coulomb_nm, nominal.viscous_nm_s)  # the model knows nominal friction
            reserve_nm = np.array(nominal.coulomb_nm) + np.array(nominal.viscous_nm_s) * arm.qd_max
        if gear_feedforward and getattr(sim, "elastic", False):
            from orc_rpl.servo.gear_observer import GearTorqueObserver
            from orc_rpl.servo.two_mass import GearTwist, smoothing_windows_s

            k_gear, rotor = sim.plant.gear_stiffness_nm_rad, sim.motor_inertia_kg_m2
            twist = GearTwist(k_gear, rotor, loop.period_s)
            servo = loop.servo
            twist.integral_of = lambda: servo.integral   # the torque the model lacks twists the gears too
            loop.set_gear_twist(twist)
            if gear_observer:   # what the model lacks as the gears' torque shows it, not as the integral holds it
                observer = GearTorqueObserver(rotor, k_gear, servo.inverse_dynamics)
                observer.friction_of = servo.friction_in_use
                loop.set_gear_observer(observer)
                twist.excess_of = lambda: observer.excess_nm
            smoothing = smoothing_windows_s(arm, rotor, k_gear)
            if scaled_averaging:   # the state feedback damps the modes: as much of them as a move's steps twist the gears
                gear_steps = GearSteps(tuple(rotor), tuple(1.0 / np.asarray(k_gear, dtype=float)))
            if state_feedback:   # the two-mass joints' state feedback instead of the cascade and its twist
                from orc_rpl.servo.state_feedback import TwoMassStateFeedback

                loop.set_gear_observer(None)
                loop.set_state_feedback(TwoMassStateFeedback(servo.arm, rotor, k_gear, sim.plant.gear_damping_nm_s,
                                                             loop.period_s))
        loop.reset(start)
        be: Any = ServoBackend(loop)
    elif backend == "kinematic":
        be = KinematicBackend(start, 0.001, lambda q, qd, qdd: np.array(arm.inverse_dynamics(q, qd, qdd)))
    else:
        raise UsageError(f"backend must be 'servo' or 'kinematic', not {backend!r}")
    layer = MotionLayer(kin, be, motion_period_s, realtime=realtime, logger=logger)
    layer.smoothing_s = smoothing  # elastic gears: no torque steps into them (trajectories averaged over their periods)
    layer.planner.gear_steps = gear_steps
    # the next move is planned on a worker thread, over an arm model of its own (made when first needed)
    layer.ahead = PlanAhead(lambda: _ahead_planner(layer, robot), paced=realtime)
    if backend == "servo" and plant == "realistic" and not servo_arm:
        layer.planner.friction_reserve_nm = reserve_nm
        layer.winding = WindingTemperature(nominal.torque_per_amp_nm_a, nominal.winding_resistance_ohm,
                                           nominal.winding_rth_k_w, nominal.winding_time_constant_s, nominal.ambient_c,
                                           motion_period_s, COPPER_TEMPCO_1_K)
        layer.winding.measurement = be.loop.cell.winding_measurement  # corrected from the drives' V and i
        layer.gear_friction = GearFriction(nominal.coulomb_nm, nominal.viscous_nm_s, nominal.gear_rth_k_w,
                                           nominal.gear_time_constant_s, nominal.cold_friction_factor,
                                           nominal.warm_rise_k, nominal.gear_motor_heat_share,
                                           nominal.torque_per_amp_nm_a, nominal.winding_resistance_ohm,
                                           COPPER_TEMPCO_1_K, nominal.ambient_c, motion_period_s)
        if gear_feedforward:  # elastic gears with their feed-forward: the servo's friction is the estimate's (cold: higher)
            layer.gear_friction.listener = be.loop.servo.set_friction
            layer.gear_friction.reset()
    # thesis 5.3: torque-limited path following is on where torques can run short of the plan
    layer.path_velocity_control = backend == "servo" and plant == "realistic" and not servo_arm
    # A robot that is set up should move at once: a paced run would start 0.4 s late otherwise.
    preload_planning()
    if record and logger is None:
        attach_recorder(layer)
    return layer


def _ahead_planner(layer: MotionLayer, robot: str) -> Planner:
    """The plan-ahead worker's planner: an arm model of its own, the layer's averaging of trajectories from rest."""
    from orc_rpl.robot import load_robot, solve_ik

    planner = Planner(Kinematics(load_robot(robot), solve_ik), layer.dt_s, layer.sub)
    planner.smoothing_s = layer.smoothing_s
    planner.gear_steps = layer.planner.gear_steps
    return planner


def attach_recorder(layer: MotionLayer) -> None:
    """A signals Logger on the layer with q_ref, q, tau, tcp and s (`layer.logger`)."""
    from orc_rpl.signals.logger import Logger

    arm, be = layer.kin.arm, layer.backend
    log = Logger(layer.now_s)
    # the getters hand over the arrays as they are (no copies): the logger copies them into its rows
    log.submit("q_ref", lambda: layer._q_ref)
    log.submit("q", be.q)
    log.submit("tau", be.torque)
    # the TCP of the measured q, computed from the recorded q when a recording is made (the same numbers,
    # no kinematics in the cycle); q is a float array of n_joints: fk need not check it
    log.derive("tcp", "q", lambda q: arm.fk_unchecked(q)[:3, 3])
    log.submit("s", layer.progress_s)
    layer.logger = log
