"""The plant room's virtual robot: the MuJoCo cell stepped by torques at the servo rate, deterministic."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import numpy as np

from orc_rpl.errors import UsageError
from orc_rpl.plant.axes import AxisDrives
from orc_rpl.plant.cell import ROBOT_PREFIX, CellDescription, build_spec, default_cell
from orc_rpl.plant.gl import import_mujoco, render_error, request_rendering
from orc_rpl.plant.io import CellIO

# No OpenGL unless a picture is requested (plant.gl); MuJoCo reads MUJOCO_GL when it is first imported.
mujoco = import_mujoco()

mj_step = mujoco.mj_step  # looked up once: step() runs a thousand times per simulated second

#: A holding brake's torque as a share of its motor's peak torque (spring-applied brakes hold more than
#: the motor can give: about 1.5 times is usual).
BRAKE_SHARE = 1.5
#: MuJoCo's no-slip iterations while the brakes hold: a braked joint does not creep.
BRAKE_NOSLIP_ITERATIONS = 20
#: A pair of bodies that touched (a collision) counts as apart again once it has stayed apart this long (s): an
#: arm stopped on an obstacle rebounds, and through elastic gears its links swing back onto it once (the IRB
#: 2400's: apart for 36 ms, touching again 77 ms after the collision), which is the same collision, not a new one
#: to stop the back-off for. Longer than the slowest period of the elastic IRB 2400's links (0.164 s, j1).
REBOUND_S = 0.2


def site_pose(data: Any, site: int) -> np.ndarray:
    """A site's pose (4x4, world) in MuJoCo data after its kinematics: the flange's, of a cell or of a copy of it."""
    t = np.eye(4)
    t[:3, :3] = data.site_xmat[site].reshape(3, 3)
    t[:3, 3] = data.site_xpos[site]
    return t


class SimCell:
    """The simulated cell: robot joints driven by torque motors, 1 kHz steps, simulated IO.

    Same inputs give bit-identical trajectories; it runs about 100 times faster than real time
    unless `realtime=True` paces it to the wall clock.
    """

    def __init__(self, robot: str | None = None, cell: CellDescription | None = None, realtime: bool = False) -> None:
        """The default cell with `robot` ("irb2400" if None), or the given cell description."""
        if cell is not None and robot is not None and robot != cell.robot:
            raise UsageError(f"robot {robot!r} differs from the cell description's robot {cell.robot!r}")
        self.description = cell if cell is not None else default_cell(robot or "irb2400")
        self.robot: str = self.description.robot
        try:
            self._spec = self._edited(build_spec(self.description))
            self._model = self._spec.compile()
        except ValueError as exc:  # MuJoCo's compile errors
            raise UsageError(f"cannot build the cell for robot {self.robot!r}: {exc}") from None
        m = self._model
        # Collision detection is about a tenth of a step even when nothing can touch; skip it when no
        # two geoms can collide (the default cell: contype = conaffinity = 0 everywhere): same numbers.
        if m.npair == 0 and not (int(np.bitwise_or.reduce(m.geom_contype)) & int(np.bitwise_or.reduce(m.geom_conaffinity))):
            m.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
        self._data = mujoco.MjData(m)
        self.n_joints: int = int(m.nactuator) - len(self.description.axes)  # the axes' drives come after the robot's
        joint_ids = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, f"{ROBOT_PREFIX}j{i + 1}") for i in range(self.n_joints)]
        if min(joint_ids) < 0:
            raise UsageError(f"robot {self.robot!r}: its MJCF must name its joints j1..j{self.n_joints}")
        self._qpos = np.array([m.jnt_qposadr[j] for j in joint_ids])
        self._qvel = np.array([m.jnt_dofadr[j] for j in joint_ids])
        # Fast path: the robot's joints are the model's only ones, in order.
        self._contiguous = bool(np.array_equal(self._qpos, np.arange(self.n_joints)) and m.nv == self.n_joints)
        # Views into MjData (its arrays live as long as it does): the servo loop reads and writes
        # through them instead of making and copying arrays every step.
        self._ctrl = self._data.ctrl[: self.n_joints]
        self._q_live = self._data.qpos[: self.n_joints] if self._contiguous else None
        self._qd_live = self._data.qvel[: self.n_joints] if self._contiguous else None
        for view in (self._q_live, self._qd_live):
            if view is not None:
                view.flags.writeable = False
        self.tau_max = m.actuator_forcerange[: self.n_joints, 1].copy()
        self.axes = AxisDrives(mujoco, m, self._data, self.description.axes) if self.description.axes else None
        self.timestep_s: float = float(m.opt.timestep)
        self._flange_site = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, ROBOT_PREFIX + self.description.robot_spec.flange_frame)
        self._payload_body = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "payload")
        self.io = CellIO(self.description.n_digital, self.description.n_analog)
        self.realtime = realtime
        self._wall_start_s = time.perf_counter()
        self._renderer: Any = None
        # Collisions (a cell made from a world model): the first contact of the robot with anything but its work
        self.collision: tuple[str, str] | None = None  #: the two bodies of the first collision not yet cleared
        self._watch_contacts = bool(self.description.contacts)
        self._noted: set[tuple[int, int]] = set()  #: colliding geom pairs already noted, until they come apart
        self._apart_since: dict[tuple[int, int], float] = {}  #: noted pairs apart now: since when (s)
        self._work_geoms = {mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, s.name) for s in self.description.solids if s.work}
        self.brakes_engaged = False  #: the joints' holding brakes (set_brakes)
        self._noslip_iterations = int(m.opt.noslip_iterations)
        self.reset()

    def _edited(self, spec: Any) -> Any:
        """The scene before it is compiled; a plant that adds to it (elastic gears) overrides this."""
        return spec

    def _scale_links(self, plant: Any, described: str) -> None:
        """A plant description's links on the compiled model: as many joints as the robot, each moving link's mass
        and inertia times its factor (`plant.link_mass_factors`); `described` names the description in the error."""
        m = self._model
        if plant.n_joints != self.n_joints:
            raise UsageError(f"the {described} of {self.robot!r} has {plant.n_joints} joints, the robot {self.n_joints}")
        for dof, factor in zip(self._qvel, plant.link_mass_factors):
            body = int(m.jnt_bodyid[m.dof_jntid[dof]])
            m.body_mass[body] *= factor
            m.body_inertia[body] *= factor

    # -- state ----------------------------------------------------------------

    @property
    def q(self) -> np.ndarray:
        """Measured joint angles (rad), a copy."""
        if self._q_live is not None:
            return self._q_live.copy()
        return self._data.qpos[self._qpos]

    @property
    def qd(self) -> np.ndarray:
        """Measured joint speeds (rad/s), a copy."""
        if self._qd_live is not None:
            return self._qd_live.copy()
        return self._data.qvel[self._qvel]

    def live_state(self) -> tuple[np.ndarray, np.ndarray] | tuple[None, None]:
        """Read-only views (q, qd) that follow the plant step by step, or (None, None) if its joints are not contiguous."""
        return self._q_live, self._qd_live

    @property
    def tau(self) -> np.ndarray:
        """Torques the motors applied in the last step (N m, after saturation), a copy."""
        return self._data.actuator_force[: self.n_joints].copy()

    @property
    def time_s(self) -> float:
        """Simulated time since the last reset."""
        return float(self._data.time)

    def flange_pose(self) -> np.ndarray:
        """The plant's own flange pose (4x4, world), to check the controller's model against."""
        return site_pose(self._data, self._flange_site)

    # -- stepping -------------------------------------------------------------

    def reset(self, q: Any = None, qd: Any = None) -> None:
        """Back to time 0 at q (the robot's home if None) at rest or at qd; IO cleared, the payload kept."""
        mujoco.mj_resetData(self._model, self._data)
        if self.axes is not None:
            self.axes.reset()
        q0 = self.description.robot_spec.home_q_rad if q is None else q
        self._data.qpos[self._qpos] = self._checked(q0, "q")
        if qd is not None:
            self._data.qvel[self._qvel] = self._checked(qd, "qd")
        mujoco.mj_forward(self._model, self._data)
        self.io.reset()
        self.collision = None
        self._noted = set()
        self._apart_since = {}
        self._wall_start_s = time.perf_counter()

    def step(self, tau_nm: np.ndarray) -> None:
        """Apply motor torques for one timestep (saturated at the motors' limits) and advance the cell."""
        data = self._data
        self._ctrl[:] = tau_nm
        mj_step(self._model, data)
        self._after_step(data)

    def _after_step(self, data: Any) -> None:
        """What follows every step: collisions, the IO's process models, pacing to the wall clock."""
        if self._watch_contacts and (data.ncon or self._noted):
            self._check_contacts()
        if self.io.processes:
            self.io.update(data.time)
        if self.realtime:
            self._pace(data.time)

    def _check_contacts(self) -> None:
        """Note the first new contact between two bodies where neither is the robot's work (a collision).

        A pair already noted is not noted again until it has come apart (for REBOUND_S): the robot may back off.
        """
        contact, work = self._data.contact, self._work_geoms
        touching = {(min(g1, g2), max(g1, g2))
                    for g1, g2, dist in zip(contact.geom1.tolist(), contact.geom2.tolist(), contact.dist.tolist())
                    if dist <= 0.0 and g1 not in work and g2 not in work}
        now_s, apart = float(self._data.time), self._apart_since
        for pair in self._noted:
            if pair in touching:
                apart.pop(pair, None)
            elif now_s - apart.setdefault(pair, now_s) >= REBOUND_S - 1e-9:
                del apart[pair]   # came apart for good: it may collide again
        self._noted = {pair for pair in self._noted if pair in touching or pair in apart}
        new = touching - self._noted
        if new and self.collision is None:
            pair = min(new)
            self._noted.add(pair)
            robot_first = pair if self._model.geom_contype[pair[0]] == 2 else pair[::-1]  # the robot or its tool first
            self.collision = (self._body_of_geom(robot_first[0]), self._body_of_geom(robot_first[1]))

    def _body_of_geom(self, geom: int) -> str:
        """A geom's name for people: a solid's or the floor's own name, else its body's (robot link, without prefix)."""
        m = self._model
        name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, geom)
        if name:
            return name
        body = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, int(m.geom_bodyid[geom])) or "world"
        return body.removeprefix(ROBOT_PREFIX)

    def clear_collision(self) -> None:
        """Forget the collision noted (after the controller has stopped the robot); the next contact is noted again."""
        self.collision = None

    def _pace(self, time_s: float) -> None:
        """Wait until the wall clock catches up with simulated time (realtime=True)."""
        ahead_s = time_s - (time.perf_counter() - self._wall_start_s)
        if ahead_s > 0.002:
            time.sleep(ahead_s)

    def set_brakes(self, engaged: bool) -> None:
        """Engage or release the joints' holding brakes (drives off: OFF mode).

        A brake holds its joint with BRAKE_SHARE times the motor's peak torque, as friction on the
        joint (MuJoCo's frictionloss). That is a soft constraint (a held joint would creep by tens of
        milliradians a second under gravity): while the brakes are engaged MuJoCo's no-slip solver
        makes it hard (BRAKE_NOSLIP_ITERATIONS; measured: 9 micro-radians in 2 s under full load).
        """
        self.brakes_engaged = bool(engaged)
        self._model.opt.noslip_iterations = BRAKE_NOSLIP_ITERATIONS if engaged else self._noslip_iterations
        self._apply_joint_friction(np.zeros(self.n_joints))

    def _apply_joint_friction(self, coulomb_nm: np.ndarray) -> None:
        """The joints' friction loss: their own Coulomb friction, plus the brakes' holding torque when engaged."""
        holding = coulomb_nm + BRAKE_SHARE * self.tau_max if self.brakes_engaged else coulomb_nm
        self._model.dof_frictionloss[self._qvel] = holding

    def push(self, force_n: Any, point_m: Any) -> None:
        """An external force (world frame, N) on the flange's body at a world point (a tool's contact with the
        work), from the next step on until pushed again (zero to release): the arm feels what it touches."""
        body, data = self._payload_body, self._data
        force = np.asarray(force_n, dtype=float)
        data.xfrc_applied[body, :3] = force
        data.xfrc_applied[body, 3:] = np.cross(np.asarray(point_m, dtype=float) - data.xipos[body], force)

    def set_payload(self, mass_kg: float, com_m: Any = (0.0, 0.0, 0.0)) -> None:
        """Put a point-like mass on the flange (com in the flange frame); the plant feels it from the next step."""
        com = np.asarray(com_m, dtype=float).reshape(-1)
        if not (np.isfinite(mass_kg) and mass_kg >= 0.0) or com.shape != (3,) or not np.all(np.isfinite(com)):
            raise UsageError(f"payload must be a mass >= 0 kg and a finite 3-vector centre, got {mass_kg!r}, {com_m!r}")
        b = self._payload_body
        self._model.body_mass[b] = mass_kg
        self._model.body_ipos[b] = com
        # A tiny inertia keeps the body well-formed; a point mass has none of its own.
        self._model.body_inertia[b] = 1e-9 if mass_kg > 0.0 else 0.0

    def _checked(self, value: Any, what: str) -> np.ndarray:
        v = np.asarray(value, dtype=float).reshape(-1)
        if v.shape != (self.n_joints,) or not np.all(np.isfinite(v)):
            raise UsageError(f"{what} must be {self.n_joints} finite numbers, got {value!r}")
        return v

    # -- pictures -------------------------------------------------------------

    def render_png(self, path: str | Path, width: int = 640, height: int = 480, camera: str = "overview") -> Path:
        """Write an offscreen picture of the cell; a clear UsageError when no OpenGL is available."""
        request_rendering()
        try:
            if self._renderer is None or (self._renderer.width, self._renderer.height) != (width, height):
                self._renderer = mujoco.Renderer(self._model, height, width)
            self._renderer.update_scene(self._data, camera=camera)
            pixels = self._renderer.render()
        except Exception as exc:  # no GL context, too large an image...
            raise render_error(exc) from None
        import matplotlib

        matplotlib.use("Agg")
        from matplotlib import image

        out = Path(path)
        image.imsave(out, pixels)
        return out

    def close(self) -> None:
        """Free the renderer's GL context, if one was made."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
