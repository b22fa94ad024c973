"""The plant room's realistic virtual robot: friction that warms up, hot windings, encoders and masses the model does not know."""

from __future__ import annotations

from typing import Any

import numpy as np

from orc_rpl.plant import compiled
from orc_rpl.plant.cell import CellDescription
from orc_rpl.plant.drives import DRIVE_INPUTS, PidDrives
from orc_rpl.plant.sim import BRAKE_SHARE, SimCell, mj_step
from orc_rpl.robot.plants import COPPER_TEMPCO_1_K, PlantSpec, plant_spec

#: The slow states (temperatures, friction) are updated every this many steps (50 ms) from the mean
#: squared torque since the last update: their time constants are 15 s (windings) to 20 min (gearboxes).
THERMAL_EVERY_STEPS = 50

#: Rows of velocity noise drawn at once from the seeded generator (no repetition: a new block when used up).
NOISE_BLOCK = 8192

#: The drives' measurement of each winding (1 sigma, seeded): terminal voltage (V) and current (A).
VOLTAGE_NOISE_V, CURRENT_NOISE_A = 0.05, 0.02

#: Where the joints' Coulomb friction (frictionloss: a row per motor joint) is a model's only constraint (no
#: two geoms can touch), MuJoCo solves it by PGS without islands: on these few rows PGS reaches the forces of
#: MuJoCo's default Newton solver in one or two sweeps, without Newton's line search and Hessian
#: factorisation, and the arm's joints are one chain (one island: the search for more is wasted). A cell with
#: contacts keeps Newton and islands, which converge on contacts in fewer, surer iterations. False: MuJoCo's
#: defaults everywhere (bench_motion.py compares the two).
LEAN_FRICTION_SOLVER = True

multiply, add, rint = np.multiply, np.add, np.rint


class RealisticCell(SimCell):
    """A SimCell whose robot is not the controller's model (see `PlantSpec` and docs/robots.md).

    `q`, `qd` and `live_state()` are what the servo measures (quantised angles, noisy speeds);
    `true_q` and `true_qd` are the plant's own. Starts cold; `warm_up()` puts it at its warm state.
    Deterministic for a seed. Its motors are `drives` (plant.drives.PidDrives), made when the model is.
    """

    drives: PidDrives

    def __init__(self, robot: str | None = None, cell: CellDescription | None = None, realtime: bool = False,
                 seed: int = 0, spec: PlantSpec | None = None, elastic: bool = False) -> None:
        """`elastic`: elastic gears, for a robot whose plant description has a gear stiffness (off by default)."""
        self.plant = spec if spec is not None else plant_spec(robot or (cell.robot if cell is not None else "irb2400"))
        self.seed = int(seed)
        if elastic and self.plant.gear_stiffness_nm_rad is None:
            from orc_rpl.errors import UsageError

            raise UsageError(f"robot {self.plant.robot!r} has no gear stiffness in its plant description")
        self.elastic = elastic
        super().__init__(robot, cell, realtime)

    def _edited(self, spec: Any) -> Any:
        """The drives as MuJoCo PID actuators, and elastic gears when asked for.

        Drives: each motor is a `pid` actuator with position, velocity and feed-forward inputs, so the
        servo's loops can run in C inside mj_step (`PidDrives.set_drive_gains`, `drive`); with its gains at zero
        (`torque_mode`, the state after reset) it is a plain torque motor: the force is the feed-forward
        input, saturated at the motor's limit. The integrator is MuJoCo's Euler (joint damping still
        implicit): the drive's torque is then computed from the state at the start of each step and held
        over it, as a digital drive does, and equals the Python servo law's (implicitfast would treat the
        drive's velocity gain implicitly: a different, unphysical loop).

        Elastic gears: a second hinge on each link, about the same axis, with the gear's stiffness.
        The first hinge (jN, the motor's, with the rotor's armature, the friction and the encoder) and
        the second (jN_gear, the gear's twist) turn one body in series: the rotor turns at the first
        angle, the link at the sum, and the spring acts on the difference (a two-mass joint).
        """
        import mujoco

        from orc_rpl.plant.cell import ROBOT_PREFIX

        spec.option.integrator = mujoco.mjtIntegrator.mjINT_EULER
        for actuator in spec.actuators:
            if actuator.name.startswith(ROBOT_PREFIX):
                low, high = list(actuator.forcerange)
                # non-zero gains at compile time: MuJoCo gives the actuator its integral state only then
                actuator.set_to_pid(kp=1.0, kv=1.0, ki=1.0, imax=1.0, ctrlspec=int(DRIVE_INPUTS))
                actuator.forcelimited, actuator.forcerange = True, [low, high]
        if not self.elastic:
            return spec
        p = self.plant
        for i, (k, damping) in enumerate(zip(p.gear_stiffness_nm_rad, p.gear_damping_nm_s)):  # type: ignore[arg-type]
            joint = spec.joint(f"{ROBOT_PREFIX}j{i + 1}")
            joint.parent.add_joint(name=f"{ROBOT_PREFIX}j{i + 1}_gear", type=mujoco.mjtJoint.mjJNT_HINGE,
                                   axis=list(joint.axis), pos=list(joint.pos), stiffness=k, damping=damping)
        return spec

    @property
    def link_q(self) -> np.ndarray:
        """The links' angles (rad): the motors' plus the gears' twist (the motors' when the gears are rigid)."""
        q = self.true_q
        if self.elastic:
            q = q + self._data.qpos[self._qpos + 1]
        return q

    @property
    def motor_inertia_kg_m2(self) -> np.ndarray:
        """Each motor joint's rotor inertia at the joint (the MJCF's armature): the motor side of an elastic gear."""
        return self._model.dof_armature[self._qvel].copy()

    # -- set-up ------------------------------------------------------------------------

    def _setup(self) -> None:
        """Arrays of the realistic plant, made once the model is compiled (called from reset the first time)."""
        p, n = self.plant, self.n_joints
        self._scale_links(p, "plant description")
        self._use_friction_solver()
        self._hidden_flange_kg = p.unmodelled_flange_mass_kg
        self._coulomb = np.array(p.coulomb_nm) * p.plant_coulomb_factor
        self._viscous = np.array(p.viscous_nm_s) * p.plant_viscous_factor
        self._k_amp = np.array(p.torque_per_amp_nm_a)
        self._r_ohm = np.array(p.winding_resistance_ohm) * p.plant_resistance_factor
        self._w_rth = np.array(p.winding_rth_k_w) * p.plant_winding_rth_factor
        dt = THERMAL_EVERY_STEPS * self.timestep_s
        self._w_decay = np.exp(-dt / (np.array(p.winding_time_constant_s) * p.plant_winding_time_factor))
        self._g_rth = np.array(p.gear_rth_k_w)
        self._g_decay = float(np.exp(-dt / p.gear_time_constant_s))
        self._rad_per_count = 2.0 * np.pi / p.encoder_counts_per_rev
        self._count_per_rad = 1.0 / self._rad_per_count
        self._tau_sq_sum = np.zeros(n)
        self._work = np.zeros(n)
        self._q_meas = np.zeros(n)
        self._qd_meas = np.zeros(n)
        self._q_meas_view = self._q_meas.view()
        self._qd_meas_view = self._qd_meas.view()
        for view in (self._q_meas_view, self._qd_meas_view):
            view.flags.writeable = False
        self.drives = PidDrives(self)
        self._kernels: Any = compiled.kernels("orc_rpl.plant.drive_kernels")   #: None where numba is not
        self._brake_nm = BRAKE_SHARE * self.tau_max   #: the brakes' holding torque on top of friction
        #: `_heat` compiled: the same operations, but exp and pow from the C library, which differ from numpy's
        #: in the last bit now and then (False: numpy's, the reference)
        self.compiled_heat = True
        self.drives.torque_mode()
        self.set_payload(0.0)

    def _use_friction_solver(self) -> None:
        """PGS without islands for a model whose only constraints are the joints' friction (LEAN_FRICTION_SOLVER):
        the same motion (tests/plant/test_realistic.py), a quarter less time per step on the elastic IRB 2400
        (5.4 -> 4.1 us: bench_motion.py --only elastic_state_feedback, elastic_plant_mj_step_us)."""
        import mujoco

        m, no = self._model, mujoco.mjtDisableBit
        if LEAN_FRICTION_SOLVER and m.opt.disableflags & int(no.mjDSBL_CONTACT) and not m.neq:
            m.opt.solver = mujoco.mjtSolver.mjSOL_PGS
            m.opt.disableflags |= int(no.mjDSBL_ISLAND)

    # -- state -------------------------------------------------------------------------

    @property
    def q(self) -> np.ndarray:
        """Measured joint angles (rad): the encoder's, quantised; a copy."""
        return self._q_meas.copy()

    @property
    def qd(self) -> np.ndarray:
        """Measured joint speeds (rad/s), with the encoder's noise; a copy."""
        return self._qd_meas.copy()

    @property
    def tau(self) -> np.ndarray:
        """Torques the motors applied in the last step (N m, after saturation), a copy (of the drives' view:
        the servo loop reads it every motion cycle)."""
        return self.drives.force.copy()

    @property
    def true_q(self) -> np.ndarray:
        """The plant's own joint angles (rad), which no controller can read; a copy."""
        return self._data.qpos[self._qpos]

    @property
    def true_qd(self) -> np.ndarray:
        """The plant's own joint speeds (rad/s); a copy."""
        return self._data.qvel[self._qvel]

    def live_state(self) -> tuple[np.ndarray, np.ndarray]:
        """Read-only views of the measured (q, qd), updated step by step."""
        return self._q_meas_view, self._qd_meas_view

    def true_live_state(self) -> tuple[np.ndarray, np.ndarray]:
        """The plant's own (q, qd) as read-only views that follow it step by step (copies if its joints are not contiguous)."""
        if self._q_live is not None:
            return self._q_live, self._qd_live
        return self.true_q, self.true_qd

    def noise_rows(self, n_steps: int) -> np.ndarray:
        """The speed noise the servo reads during the next n_steps steps (one row a step, the current first)."""
        end = self._noise_row + n_steps
        if end >= len(self._noise):
            self._noise = np.concatenate([self._noise[self._noise_row:], self._new_noise()])
            self._noise_row, end = 0, n_steps
        return self._noise[self._noise_row:end]

    @property
    def winding_temperature_c(self) -> np.ndarray:
        """Each motor's winding temperature (C)."""
        return self.plant.ambient_c + self.winding_rise_k

    def winding_measurement(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """What each drive measures of its winding now: (terminal voltage V, current A, joint speed rad/s).

        The winding is a resistance R20 (1 + 0.00393 (T - 20 C)) with the back-EMF k * speed (k the
        torque per ampere: SI units, joint side); no inductance (a 4 ms cycle is long against the
        electrical time constant). Voltage and current carry seeded noise (VOLTAGE_NOISE_V,
        CURRENT_NOISE_A, 1 sigma); the speed is the one the servo reads.
        """
        if compiled.ON and self._kernels is not None:
            noise, out = self._drive_rng.standard_normal((2, self.n_joints)), np.empty((3, self.n_joints))
            self._kernels.winding_sample(self.drives.force, self._k_amp, self._r_ohm, self.winding_rise_k, self.plant.ambient_c,
                           COPPER_TEMPCO_1_K, self._data.qvel, self._qvel, self._qd_meas, noise, VOLTAGE_NOISE_V,
                           CURRENT_NOISE_A, out)
            return out[0], out[1], out[2]
        current = self.drives.force / self._k_amp
        resistance = self._r_ohm * (1.0 + COPPER_TEMPCO_1_K * (self.plant.ambient_c + self.winding_rise_k - 20.0))
        speed = self._qd_meas.copy()
        voltage = resistance * current + self._k_amp * self.true_qd
        noise = self._drive_rng.standard_normal((2, self.n_joints))
        return voltage + VOLTAGE_NOISE_V * noise[0], current + CURRENT_NOISE_A * noise[1], speed

    @property
    def friction_factor(self) -> np.ndarray:
        """Friction now over warm friction, per joint (cold_friction_factor at a cold start, 1.0 warm)."""
        p = self.plant
        return 1.0 + (p.cold_friction_factor - 1.0) * np.exp(-self.gear_rise_k / p.warm_rise_k)

    def friction_nm(self) -> tuple[np.ndarray, np.ndarray]:
        """The plant's (Coulomb N m, viscous N m s/rad) friction now."""
        f = self.friction_factor
        return self._coulomb * f, self._viscous * f

    # -- stepping ----------------------------------------------------------------------

    def reset(self, q: Any = None, qd: Any = None) -> None:
        """Back to time 0 at q, at rest; temperatures kept (a reset is not a night's cooling: see `cool_down`)."""
        if not hasattr(self, "_tau_sq_sum"):
            self._setup()
            self.cool_down()
        super().reset(q, qd)
        if self.elastic:
            self._wind_gears()
        self._rng = np.random.default_rng(self.seed)
        self._drive_rng = np.random.default_rng([self.seed, 1])  # its own stream: the speed noise is unchanged
        self._noise = self._new_noise()
        self._noise_row = 0
        self._steps = self._heated_at = 0
        self._tau_sq_sum[:] = 0.0
        self._measure()

    def _wind_gears(self) -> None:
        """Each gear twisted as it is at rest under the links' weight (a robot at rest is not one whose
        links were just let go: k * twist = -gravity torque, found in a few fixed-point passes)."""
        import mujoco

        data, gear_q, gear_v = self._data, self._qpos + 1, self._qvel + 1
        stiffness = np.array(self.plant.gear_stiffness_nm_rad)
        for _ in range(4):
            data.qpos[gear_q] = -data.qfrc_bias[gear_v] / stiffness
            mujoco.mj_forward(self._model, data)

    def cool_down(self) -> None:
        """A cold start: windings and gearboxes at ambient, friction at its cold value."""
        self.winding_rise_k = np.zeros(self.n_joints)
        self.gear_rise_k = np.zeros(self.n_joints)
        self._apply_friction()

    def warm_up(self, gear_rise_k: float = 30.0) -> None:
        """A robot that has run a while: gearboxes `gear_rise_k` above ambient (friction about warm)."""
        self.gear_rise_k = np.full(self.n_joints, float(gear_rise_k))
        self._apply_friction()

    def step(self, tau_nm: np.ndarray) -> None:
        """Apply motor torques for one timestep, advance the cell, update what the servo measures.

        The drives must be in torque mode (`PidDrives.torque_mode`, their state after a reset): the
        torque is their feed-forward input.
        """
        data = self._data
        self.drives.ff_in[:] = tau_nm
        mj_step(self._model, data)
        self._copper()
        self._next_noise_row()
        self._measure()
        self._after_step(data)

    def _copper(self) -> None:
        """The copper losses of the last step for the thermal model; the slow states every THERMAL_EVERY_STEPS."""
        work, tau = self._work, self.drives.force
        multiply(tau, tau, work)
        add(self._tau_sq_sum, work, self._tau_sq_sum)
        self._steps += 1
        if self._steps - self._heated_at == THERMAL_EVERY_STEPS:
            self._heat()

    def _copper_rows(self, forces: np.ndarray) -> None:
        """The copper losses of a drive call's steps (their forces, overwritten); the slow states once
        THERMAL_EVERY_STEPS have passed (at the call's end: whole motion cycles)."""
        multiply(forces, forces, forces)
        add(self._tau_sq_sum, add.reduce(forces, 0), self._tau_sq_sum)  # = forces.sum(axis=0), one C call
        self._count_steps(len(forces))

    def _count_steps(self, n_steps: int) -> None:
        """n_steps more steps whose copper losses are summed; the slow states once THERMAL_EVERY_STEPS have passed."""
        self._steps += n_steps
        if self._steps - self._heated_at >= THERMAL_EVERY_STEPS:
            self._heat(self._steps - self._heated_at)

    def _next_noise_row(self) -> None:
        """On to the next row of noise (the next measurement's), drawing a new block at the end of this one."""
        self._noise_row += 1
        if self._noise_row == len(self._noise):
            self._noise, self._noise_row = self._new_noise(), 0

    def _new_noise(self) -> np.ndarray:
        """The next block of speed noise from the seeded generator."""
        return self._rng.standard_normal((NOISE_BLOCK, self.n_joints)) * self.plant.velocity_noise_rad_s

    def _measure(self) -> None:
        """Encoder quantisation and velocity noise (the current row) on the plant's state (no allocation)."""
        data, qm, qdm = self._data, self._q_meas, self._qd_meas
        if self._q_live is not None:
            multiply(self._q_live, self._count_per_rad, qm)
            add(self._qd_live, self._noise[self._noise_row], qdm)
        else:
            multiply(data.qpos[self._qpos], self._count_per_rad, qm)
            add(data.qvel[self._qvel], self._noise[self._noise_row], qdm)
        rint(qm, qm)
        multiply(qm, self._rad_per_count, qm)

    def _heat(self, n_steps: int = THERMAL_EVERY_STEPS) -> None:
        """Windings and gearboxes over the last n_steps steps; friction follows the gearboxes."""
        p = self.plant
        if compiled.ON and self._kernels is not None and self.compiled_heat:   # plant/drive_kernels.py
            new = np.empty((4, self.n_joints))   # new arrays, as below: a caller may hold the old ones
            self._kernels.heat(self._tau_sq_sum, n_steps, THERMAL_EVERY_STEPS, self._w_decay, self._g_decay, self._r_ohm,
                               self._k_amp, self._w_rth, self._g_rth, COPPER_TEMPCO_1_K, p.ambient_c,
                               p.gear_motor_heat_share, p.cold_friction_factor, p.warm_rise_k, self.winding_rise_k,
                               self.gear_rise_k, self._coulomb_now, self._viscous_now, self._coulomb, self._viscous,
                               self._data.qvel, self._qvel, self._brake_nm, self.brakes_engaged,
                               self._model.dof_damping, self._model.dof_frictionloss, new)
            self.winding_rise_k, self.gear_rise_k, self._coulomb_now, self._viscous_now = new
            self._heated_at = self._steps
            return
        mean_tau_sq = self._tau_sq_sum / n_steps
        self._tau_sq_sum[:] = 0.0
        self._heated_at = self._steps
        w_decay, g_decay = self._w_decay, self._g_decay
        if n_steps != THERMAL_EVERY_STEPS:  # a drive call ended the period (whole motion cycles)
            w_decay, g_decay = w_decay ** (n_steps / THERMAL_EVERY_STEPS), g_decay ** (n_steps / THERMAL_EVERY_STEPS)
        resistance = self._r_ohm * (1.0 + COPPER_TEMPCO_1_K * (p.ambient_c + self.winding_rise_k - 20.0))
        copper_w = resistance * mean_tau_sq / (self._k_amp * self._k_amp)
        self.winding_rise_k = w_decay * self.winding_rise_k + (1.0 - w_decay) * self._w_rth * copper_w
        qd = np.abs(self.true_qd)
        heat_w = self._coulomb_now * qd + self._viscous_now * qd * qd + p.gear_motor_heat_share * copper_w
        self.gear_rise_k = g_decay * self.gear_rise_k + (1.0 - g_decay) * self._g_rth * heat_w
        self._apply_friction()

    def _apply_friction(self) -> None:
        """Friction for the gearboxes' temperature, written into the model (no recompile needed)."""
        self._coulomb_now, self._viscous_now = self.friction_nm()
        self._model.dof_damping[self._qvel] = self._viscous_now
        self._apply_joint_friction(self._coulomb_now)

    def set_brakes(self, engaged: bool) -> None:
        """Engage or release the brakes (see SimCell.set_brakes), on top of the joints' own friction now."""
        super().set_brakes(engaged)
        self._apply_joint_friction(self._coulomb_now)

    def set_payload(self, mass_kg: float, com_m: Any = (0.0, 0.0, 0.0)) -> None:
        """The payload on the flange, plus the dress pack the controller's model does not have."""
        super().set_payload(mass_kg + self._hidden_flange_kg, com_m)
        self.payload_kg = float(mass_kg)
