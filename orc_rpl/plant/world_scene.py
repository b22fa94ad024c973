"""The plant room's cell made from a world model: every object with a shape becomes a solid the robot can touch."""

from __future__ import annotations

import numpy as np

from orc_rpl.errors import UsageError
from orc_rpl.plant.axes import AxisDrive
from orc_rpl.plant.cell import CellDescription, Solid
from orc_rpl.world.axes import DIRECTIONS
from orc_rpl.world.objects import ROBOT
from orc_rpl.world.world import World

#: What an axis drive is tuned for when the world does not say: a track's carriage with a robot (kg), a
#: positioner's table with its workpiece (kg m2 about the axis).
TRACK_MASS_KG = 600.0
POSITIONER_INERTIA_KG_M2 = 5.0
#: The moving mass of a conveyor's belt with its parts (kg), what its drive is tuned for.
BELT_MASS_KG = 50.0

#: Colour names a world model may use, as RGBA.
COLOURS: dict[str, tuple[float, float, float, float]] = {
    "grey": (0.6, 0.6, 0.62, 1.0), "gray": (0.6, 0.6, 0.62, 1.0), "orange": (0.95, 0.5, 0.1, 1.0),
    "red": (0.8, 0.15, 0.1, 1.0), "green": (0.2, 0.65, 0.25, 1.0), "blue": (0.15, 0.35, 0.8, 1.0),
    "yellow": (0.95, 0.85, 0.2, 1.0), "black": (0.1, 0.1, 0.1, 1.0), "white": (0.95, 0.95, 0.95, 1.0),
    "brown": (0.55, 0.4, 0.25, 1.0), "silver": (0.75, 0.75, 0.78, 1.0),
}
SHAPES = {"box": 3, "cylinder": 2, "sphere": 1}  #: geometry -> number of sizes it takes


def cell_from_world(world: World, robot: str | None = None) -> CellDescription:
    """The simulated cell of a world model: its shaped objects as solids around its robot, contacts on.

    The scene's origin is the robot's base (the controller's kinematics start there); the world's
    objects are placed relative to it. Objects without a shape (frames only) and meshes are left out
    (a mesh is for pictures, not contacts).
    """
    entry = world.robot
    name = robot or (entry.model if entry is not None else "irb2400")
    base = np.eye(4)
    if entry is not None:
        base = world.world_pose(ROBOT).matrix()   # with the moving frames at their homes
        if not np.allclose(base[:3, :3], np.eye(3), atol=1e-9):
            raise UsageError(f"{world.path}: the simulated cell puts the robot upright; its base may only be moved, not turned")
    axes = scene_axes(world, base)
    mount_of = {o.name: moving_ancestor(world, o.name) for o in world.objects}
    robot_mount = moving_ancestor(world, ROBOT)
    robot_base = (world.relative_pose(ROBOT, robot_mount).matrix() if robot_mount else np.eye(4))[:3, 3]
    solids = []
    for obj in world.objects:
        model = obj.model
        if model is None or model.geometry not in SHAPES:
            continue
        if len(model.size_m) != SHAPES[model.geometry] or min(model.size_m) <= 0.0:
            raise UsageError(f"{world.path}: object '{obj.name}': a {model.geometry} needs {SHAPES[model.geometry]} "
                             f"positive sizes, got {model.size_m}")
        on_flange = "flange" in world.ancestors(obj.name)
        mount = "" if on_flange else mount_of[obj.name]
        if on_flange:
            frame = world.relative_pose(obj.name, "flange").matrix()
        elif mount:
            frame = world.relative_pose(obj.name, mount).matrix()
        else:
            frame = np.linalg.inv(base) @ world.world_pose(obj.name).matrix()
        centre = frame @ (model.offset.matrix() if model.offset is not None else np.eye(4))
        solids.append(Solid(obj.name, model.geometry, tuple(model.size_m), tuple(float(v) for v in centre[:3, 3]),
                            tuple(float(v) for v in centre[:3, :3].reshape(-1)), on_flange, obj.work,
                            _rgba(model.colour), mount))
    if robot_mount:
        robot_base = tuple(float(v) for v in robot_base)
    return CellDescription(robot=name, solids=tuple(solids), contacts=True, notes=(f"made from {world.path}",),
                           axes=axes, robot_mount=robot_mount,
                           robot_base_m=tuple(robot_base) if robot_mount else (0.0, 0.0, 0.0))


def _rgba(colour: object) -> tuple[float, float, float, float]:
    if isinstance(colour, str):
        return COLOURS.get(colour.lower(), COLOURS["grey"])
    if isinstance(colour, tuple) and len(colour) in (3, 4):
        values = tuple(float(v) for v in colour)
        return values if len(values) == 4 else (*values, 1.0)  # type: ignore[return-value]
    return COLOURS["grey"]


def moving_ancestor(world: World, name: str) -> str:
    """The nearest moving frame among an object's ancestors (what carries it in the cell), "" for none."""
    for above in world.ancestors(name):
        if above in world and above not in (ROBOT, "world", "flange") and world.object(above).axis is not None:
            return above
    return ""


def scene_axes(world: World, base: np.ndarray) -> tuple[AxisDrive, ...]:
    """The world's moving frames as drives of the cell, parents first: tracks and positioners, and conveyors (a belt
    whose drive runs at the belt's speed from the start; the parts on it are solids that ride on it)."""
    out = []
    moving = [n for n in world.descendants("world") if n in world.moving_frames()]
    for name in moving:
        axis = world.object(name).axis
        assert axis is not None
        parent = moving_ancestor(world, name)
        at_value = world.relative_pose(name, parent).matrix() if parent else np.linalg.inv(base) @ world.world_pose(name).matrix()
        at_zero = at_value @ np.linalg.inv(axis.matrix(world.axis_value(name)))
        conveyor = axis.joint == "conveyor"
        mass = BELT_MASS_KG if conveyor else POSITIONER_INERTIA_KG_M2 if axis.rotary else TRACK_MASS_KG
        out.append(AxisDrive(name, axis.rotary, DIRECTIONS[axis.direction], parent,
                             tuple(float(v) for v in at_zero[:3, 3]), tuple(float(v) for v in at_zero[:3, :3].reshape(-1)),
                             axis.range_si, axis.home_si, mass, axis.speed_si if conveyor else 0.0))
    return tuple(out)
