"""The plant room's description of the default cell: what stands where, kept in one place and built with MjSpec."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from orc_rpl.plant.axes import AxisDrive, add_axes, add_drives
from orc_rpl.plant.gl import import_mujoco
from orc_rpl.robot.robots import ROBOTS, RobotSpec
from orc_rpl.world.pose import rotation_zyx

#: Prefix of every robot element in the built scene ("robot/j1", "robot/flange").
ROBOT_PREFIX = "robot/"


@dataclass(frozen=True, slots=True)
class Box:
    """A fixed box in the cell (a table top, a leg, a fixture), placed in the world frame."""

    name: str
    center_m: tuple[float, float, float]
    half_size_m: tuple[float, float, float]
    rgba: tuple[float, float, float, float] = (0.55, 0.45, 0.35, 1.0)
    angles_rad: tuple[float, float, float] = (0.0, 0.0, 0.0)  #: (a, b, c): Rz(a)·Ry(b)·Rx(c), as in Pose


@dataclass(frozen=True, slots=True)
class Solid:
    """An object of a world model as the simulated cell sees it: a shape that can touch the robot.

    Placed in the world frame, or in the flange frame when `on_flange` (a tool, a holder); `work`
    marks what the robot works on (a casting to grind): touching it is no collision.
    """

    name: str
    geometry: str                                   #: "box", "cylinder" or "sphere"
    size_m: tuple[float, ...]                       #: box (x, y, z); cylinder (radius, height); sphere (radius,)
    position_m: tuple[float, float, float]          #: centre of the shape
    rotation: tuple[float, ...]                     #: its orientation, a 3x3 matrix row by row
    on_flange: bool = False
    work: bool = False
    rgba: tuple[float, float, float, float] = (0.6, 0.6, 0.62, 1.0)
    mount: str = ""                                 #: the external axis it rides on (placed in its frame), "" for none


@dataclass(frozen=True, slots=True)
class CellDescription:
    """Everything the virtual cell is made of; a world model will later generate this."""

    robot: str = "irb2400"                                    #: registry name of the robot
    robot_base_m: tuple[float, float, float] = (0.0, 0.0, 0.0)  #: robot base position in the world
    boxes: tuple[Box, ...] = ()                                #: fixed geometry (table...)
    timestep_s: float = 0.001                                  #: plant step = servo period
    n_digital: int = 16                                        #: DigIn[1..n] and DigOut[1..n]
    n_analog: int = 8                                          #: AnaIn[1..n] and AnaOut[1..n]
    camera_lookat_m: tuple[float, float, float] = (0.6, 0.0, 0.6)
    camera_distance_m: float = 3.2
    notes: tuple[str, ...] = field(default=())
    solids: tuple[Solid, ...] = ()                             #: a world model's objects (contacts on)
    contacts: bool = False                                     #: the robot collides with the floor and the solids
    axes: tuple[AxisDrive, ...] = ()                           #: external axes (track, positioner), parents first
    robot_mount: str = ""                                      #: the axis the robot's base rides on (a track), "" for none

    @property
    def robot_spec(self) -> RobotSpec:
        """The robot's registry entry (UsageError listing the known robots if the name is wrong)."""
        return ROBOTS.get(self.robot)


def table(x_m: tuple[float, float] = (0.7, 1.3), y_m: tuple[float, float] = (-0.5, 0.5),
          top_m: float = 0.35, thickness_m: float = 0.04, leg_m: float = 0.04) -> tuple[Box, ...]:
    """A table as boxes: its top spans x_m by y_m with the upper face at top_m, four legs to the floor."""
    cx, cy = sum(x_m) / 2, sum(y_m) / 2
    hx, hy = (x_m[1] - x_m[0]) / 2, (y_m[1] - y_m[0]) / 2
    boxes = [Box("table_top", (cx, cy, top_m - thickness_m / 2), (hx, hy, thickness_m / 2))]
    leg_h = (top_m - thickness_m) / 2
    for i, (sx, sy) in enumerate(((1, 1), (1, -1), (-1, 1), (-1, -1))):
        center = (cx + sx * (hx - leg_m), cy + sy * (hy - leg_m), leg_h)
        boxes.append(Box(f"table_leg{i + 1}", center, (leg_m / 2, leg_m / 2, leg_h), (0.35, 0.3, 0.25, 1.0)))
    return tuple(boxes)


def default_cell(robot: str = "irb2400") -> CellDescription:
    """The default cell: the robot at the origin (z up, x forward), a table in front, its top at 0.35 m."""
    return CellDescription(robot=robot, boxes=table(), notes=("table top x 0.7..1.3 m, y -0.5..0.5 m, z 0.35 m",))


def _camera_position(cell: CellDescription) -> tuple[float, float, float]:
    lx, ly, lz = cell.camera_lookat_m
    d = cell.camera_distance_m
    return (lx + 0.55 * d, ly - 0.7 * d, lz + 0.45 * d)


def _camera_axes(cell: CellDescription) -> tuple[float, ...]:
    """MuJoCo's xyaxes for a camera at _camera_position looking at camera_lookat_m, image up towards +z."""
    forward = np.subtract(cell.camera_lookat_m, _camera_position(cell))
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, (0.0, 0.0, 1.0))
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    return (*right, *up)


def build_spec(cell: CellDescription) -> Any:
    """The MuJoCo scene of a cell as an MjSpec: floor, light, boxes, the robot MJCF attached at its base."""
    mujoco = import_mujoco()  # the plant room wraps MuJoCo; no OpenGL backend unless a picture was requested

    spec = mujoco.MjSpec()
    spec.modelname = f"cell_{cell.robot}"
    spec.option.timestep = cell.timestep_s
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.visual.global_.offwidth = 1920
    spec.visual.global_.offheight = 1080
    spec.visual.headlight.ambient = [0.35, 0.35, 0.35]

    world = spec.worldbody
    world.add_light(name="sun", pos=[1.0, -1.0, 4.0], dir=[-0.2, 0.2, -1.0], diffuse=[0.7, 0.7, 0.7])
    # Contact groups: the cell (floor, solids) is type 1 and meets type 2, the robot and its tool the other
    # way round: the robot meets the cell, never itself, and the cell never itself.
    cell_type, cell_affinity = (1, 2) if cell.contacts else (0, 0)
    world.add_geom(name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[4.0, 4.0, 0.05],
                   rgba=[0.82, 0.84, 0.86, 1.0], contype=cell_type, conaffinity=cell_affinity)
    for box in cell.boxes:
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, rotation_zyx(*box.angles_rad).reshape(-1))
        world.add_geom(name=box.name, type=mujoco.mjtGeom.mjGEOM_BOX, pos=list(box.center_m), quat=list(quat),
                       size=list(box.half_size_m), rgba=list(box.rgba), contype=0, conaffinity=0)
    world.add_camera(name="overview", pos=list(_camera_position(cell)), xyaxes=list(_camera_axes(cell)))

    robot = mujoco.MjSpec.from_file(str(cell.robot_spec.mjcf_path))
    flange_site = robot.site(cell.robot_spec.flange_frame)
    flange_link, flange_pos, flange_quat = flange_site.parent.name, list(flange_site.pos), list(flange_site.quat)
    axis_bodies = add_axes(mujoco, spec, cell.axes)
    mount = (axis_bodies[cell.robot_mount] if cell.robot_mount else world).add_frame(pos=list(cell.robot_base_m))
    base_body = robot.worldbody.first_body()
    mount.attach_body(base_body, ROBOT_PREFIX, "")
    add_drives(mujoco, spec, cell.axes)
    if cell.robot_mount:  # the base slides over the floor on its carriage: that is no contact
        spec.add_exclude(bodyname1="world", bodyname2=base_body.name)  # already prefixed by attach_body
    # A massless body at the flange: the plant's payload, set at run time (SimCell.set_payload).
    payload = spec.body(ROBOT_PREFIX + flange_link).add_body(name="payload", pos=flange_pos, quat=flange_quat)
    if cell.contacts:
        for geom in spec.geoms:
            if geom.parent.name.startswith(ROBOT_PREFIX):
                geom.contype, geom.conaffinity = 2, 1
    for solid in cell.solids:
        size = _mujoco_size(solid)
        kind = {"box": mujoco.mjtGeom.mjGEOM_BOX, "cylinder": mujoco.mjtGeom.mjGEOM_CYLINDER,
                "sphere": mujoco.mjtGeom.mjGEOM_SPHERE}[solid.geometry]
        body, (ctype, caff) = (payload, (2, 1)) if solid.on_flange else (world, (cell_type, cell_affinity))
        if solid.mount:
            body = axis_bodies[solid.mount]
        # no mass: the plant's payload is set apart (set_payload), and a fixture weighs nothing to the robot
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, np.asarray(solid.rotation, dtype=float))
        body.add_geom(name=solid.name, type=kind, size=size, pos=list(solid.position_m), quat=list(quat),
                      rgba=list(solid.rgba), contype=ctype, conaffinity=caff, density=0.0)
    return spec


def _mujoco_size(solid: Solid) -> list[float]:
    """MuJoCo's half sizes of a solid."""
    s = solid.size_m
    if solid.geometry == "box":
        return [s[0] / 2, s[1] / 2, s[2] / 2]
    if solid.geometry == "cylinder":
        return [s[0], s[1] / 2, 0.0]
    return [s[0], 0.0, 0.0]
