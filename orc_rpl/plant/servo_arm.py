"""The plant room's arm on bus servos: each joint a geared DC motor with play, a 12-bit encoder and the servo's own position loop."""

from __future__ import annotations

from typing import Any

import numpy as np

from orc_rpl.errors import UsageError
from orc_rpl.plant.cell import ROBOT_PREFIX, CellDescription
from orc_rpl.plant.sim import SimCell, mj_step, mujoco
from orc_rpl.robot.servo_plants import ServoPlantSpec, servo_plant_spec

#: The gear play's end stops: MuJoCo joint limits, made stiff (the shortest time constant a 1 ms step allows).
PLAY_SOLREF = (0.002, 1.0)
#: The output's own damping inside the play (N m s/rad): grease, so the output does not rattle.
PLAY_DAMPING_NM_S = 0.02
#: A limp servo's gearbox sticks until back-driven harder than limp_hold_nm: a stiff, damped stick (N m/rad,
#: N m s/rad) that slips, and sticks again where it slipped to.
STICK_NM_RAD = 50.0
STICK_NM_S_RAD = 1.7

clip, rint = np.clip, np.rint
mj_forward = mujoco.mj_forward


class ServoArmCell(SimCell):
    """A SimCell whose joints are bus servos (see `ServoPlantSpec`): it takes goal positions, not torques.

    Each joint is two hinges about one axis: jN, the motor side (the rotor's armature, the gearbox's
    friction, the motor), and jN_play, the output's turn inside the gearbox's play (limited to
    +-backlash/2). The encoder sees the output (their sum). `q`, `qd` are what the servo reports
    (whole counts; speed in counts per second); `true_q` is the output's own angle. Deterministic.
    """

    def __init__(self, robot: str | None = None, cell: CellDescription | None = None, realtime: bool = False,
                 spec: ServoPlantSpec | None = None) -> None:
        name = robot or (cell.robot if cell is not None else "so101")
        found = spec if spec is not None else servo_plant_spec(name)
        if found is None:
            raise UsageError(f"robot {name!r} is not an arm on bus servos (no servo plant description)")
        self.plant = found
        super().__init__(robot, cell, realtime)

    def _edited(self, spec: Any) -> Any:
        half_deg = float(np.degrees(self.plant.backlash_rad)) / 2.0  # the scene's compiler takes degrees
        for i in range(self.plant.n_joints):
            joint = spec.joint(f"{ROBOT_PREFIX}j{i + 1}")
            joint.parent.add_joint(name=f"{ROBOT_PREFIX}j{i + 1}_play", type=mujoco.mjtJoint.mjJNT_HINGE,
                                   axis=list(joint.axis), pos=list(joint.pos), range=[-half_deg, half_deg],
                                   limited=mujoco.mjtLimited.mjLIMITED_TRUE, armature=0.0,
                                   damping=PLAY_DAMPING_NM_S, solref_limit=list(PLAY_SOLREF))
        return spec

    # -- set-up ------------------------------------------------------------------------

    def _setup(self) -> None:
        """Arrays of the servos, made once the model is compiled (called from reset the first time)."""
        p, m, n = self.plant, self._model, self.n_joints
        self._scale_links(p, "servo plant description")
        self._play = self._qpos + 1
        self._play_v = self._qvel + 1
        m.dof_frictionloss[self._qvel] = np.array(p.coulomb_nm)
        m.dof_damping[self._qvel] = np.array(p.viscous_nm_s)
        self.goal_count = np.zeros(n)
        self.enabled = np.ones(n, dtype=bool)
        self.duty_limit = np.ones(n)             #: the torque limit register as a share of full duty
        self.duty = np.zeros(n)                  #: the PWM duty of the last step (what an STS reports as load)
        self.temperature_rise_k = np.zeros(n)
        self._decay = float(np.exp(-self.timestep_s / p.winding_time_constant_s))
        self._amp_per_nm = p.stall_current_a / p.stall_torque_nm
        self._count_per_rad = 1.0 / p.rad_per_count
        self._stuck_rad = np.zeros(n)  #: where each limp servo's gearbox sticks (its motor side)
        super().set_payload(p.unmodelled_flange_mass_kg)

    # -- what the servo reports ----------------------------------------------------------------

    @property
    def true_q(self) -> np.ndarray:
        """The outputs' own angles (rad), which no encoder reads exactly; a copy."""
        return self._data.qpos[self._qpos] + self._data.qpos[self._play]

    @property
    def true_qd(self) -> np.ndarray:
        return self._data.qvel[self._qvel] + self._data.qvel[self._play_v]

    @property
    def counts(self) -> np.ndarray:
        """Present position in whole encoder counts from joint zero."""
        return rint(self.true_q * self._count_per_rad)

    @property
    def q(self) -> np.ndarray:
        """Measured joint angles (rad): the encoder's whole counts."""
        return self.counts * self.plant.rad_per_count

    @property
    def qd(self) -> np.ndarray:
        """Measured joint speeds (rad/s): whole counts per second, as the servo reports them."""
        return rint(self.true_qd * self._count_per_rad) * self.plant.rad_per_count

    def live_state(self) -> tuple[None, None]:
        return None, None

    @property
    def current_a(self) -> np.ndarray:
        """Each motor's current (A, unsigned): the share of the stall torque it gives."""
        return np.abs(self._data.actuator_force) * self._amp_per_nm * self.enabled  # a limp one's gearbox holds, unpowered

    @property
    def temperature_c(self) -> np.ndarray:
        """The servos' temperature as they report it (whole degrees C)."""
        return rint(self.plant.ambient_c + self.temperature_rise_k)

    # -- commands ----------------------------------------------------------------------

    def set_goals(self, q_rad: Any) -> None:
        """Goal positions (rad from joint zero), sent as whole counts as on the bus."""
        self.goal_count = rint(np.asarray(q_rad, dtype=float) * self._count_per_rad)

    def set_torque(self, enabled: Any) -> None:
        """Torque on or off per servo (off: limp, back-driven through the gearbox)."""
        self.enabled = np.asarray(enabled, dtype=bool).copy()

    # -- stepping ----------------------------------------------------------------------

    def reset(self, q: Any = None, qd: Any = None) -> None:
        """Back to time 0 at q (the goals there too), at rest; the servos keep their temperature."""
        if not hasattr(self, "_stuck_rad"):
            self._setup()
        super().reset(q, qd)
        # at rest, gravity has taken up each gear's play: the output is at q, the motor side behind it
        data, half = self._data, self.plant.backlash_rad / 2.0
        play = -np.sign(data.qfrc_bias[self._play_v]) * half
        data.qpos[self._play] = play
        data.qpos[self._qpos] -= play
        mj_forward(self._model, data)
        self.set_goals(self.true_q)

    def step_servos(self) -> None:
        """One step (1 ms): each servo's firmware sets its duty from the encoder, then the cell moves."""
        p, data = self.plant, self._data
        error = self.goal_count - self.counts
        error[np.abs(error) <= p.deadband_counts] = 0.0
        speed = self.qd
        duty = clip(p.position_gain_duty_per_count * error - p.damping_duty_s_rad * speed, -self.duty_limit, self.duty_limit)
        self.duty = np.where(self.enabled, duty, 0.0)
        motor_q, motor_qd = data.qpos[self._qpos], data.qvel[self._qvel]
        driven = p.stall_torque_nm * (self.duty - motor_qd / p.no_load_speed_rad_s)
        # a limp servo: its gearbox sticks where it is, and slips when back-driven beyond limp_hold_nm
        stick = STICK_NM_RAD * (self._stuck_rad - motor_q) - STICK_NM_S_RAD * motor_qd
        slipping = np.abs(stick) > p.limp_hold_nm
        self._stuck_rad = np.where(self.enabled | slipping, motor_q, self._stuck_rad)
        self._ctrl[:] = np.where(self.enabled, driven, clip(stick, -p.limp_hold_nm, p.limp_hold_nm))
        mj_step(self._model, data)
        copper_w = p.winding_resistance_ohm * self.current_a ** 2
        self.temperature_rise_k = self._decay * self.temperature_rise_k + (1.0 - self._decay) * p.winding_rth_k_w * copper_w
        self._after_step(data)

    def step(self, tau_nm: np.ndarray) -> None:
        raise UsageError("an arm on bus servos takes goal positions (step_servos), not torques")

    def set_payload(self, mass_kg: float, com_m: Any = (0.0, 0.0, 0.0)) -> None:
        """The payload on the flange, plus the cables the controller's model does not have."""
        super().set_payload(mass_kg + self.plant.unmodelled_flange_mass_kg, com_m)
        self.payload_kg = float(mass_kg)
