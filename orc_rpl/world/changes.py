"""Changes to a world: teach a frame, add an object, set a soft attribute, affix and unfix; each returns a new World."""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING

from orc_rpl.world.editing import add_object, apply, set_attribute, set_entry
from orc_rpl.world.objects import NAME_RE, PREDEFINED, WorldError
from orc_rpl.world.pose import WORLD, Pose, readable_angles
from orc_rpl.world.values import SoftValue, format_pose, format_soft

if TYPE_CHECKING:
    from orc_rpl.world.world import World


def _relative_to(world: World, pose: Pose, node: str) -> Pose:
    """`pose` (numbers relative to pose.frame, any object or predefined name) re-expressed relative to `node`."""
    if pose.frame == node:
        return pose
    if pose.frame not in world:
        raise WorldError(f"a pose relative to '{pose.frame}', which is not in {world.path}")
    # (frame in node) * (pose in frame); compose keeps the left operand's frame, `node`.
    return world.relative_pose(pose.frame, node).compose(pose)


def _check_name(name: str, what: str) -> None:
    if not NAME_RE.fullmatch(name) or name in PREDEFINED:
        raise WorldError(f"bad {what} name '{name}'")


def with_frame(world: World, owner: str, name: str, pose: Pose) -> World:
    """Add or change the named frame `owner.name`; `pose` may be relative to any frame (a taught position IN its on-line frame)."""
    _check_name(name, "frame")
    world.object(owner)
    if any(p.name == name for p in world.object(owner).paths):
        raise WorldError(f"'{owner}.{name}' is a path, not a frame")
    old = world.object(owner).frame(name)
    local = dataclasses.replace(readable_angles(_relative_to(world, pose, owner), old.pose if old else None), axes=pose.axes)
    rotary = {n for n in world.moving_frames() if world.object(n).axis.rotary}  # type: ignore[union-attr]
    return world._reloaded(apply(world.dump(), [set_entry(world.parsed, owner, "frames", name, format_pose(local, rotary))]))


def with_pose(world: World, name: str, pose: Pose) -> World:
    """Move an object (its children move with it); `pose` may be relative to any frame."""
    local = readable_angles(_relative_to(world, pose, world.object(name).parent), world.object(name).pose)
    return world._reloaded(apply(world.dump(), [set_attribute(world.parsed, name, "pose", format_pose(local))]))


def with_object(world: World, name: str, parent: str = WORLD, pose: Pose | None = None, *,
                online_frame: bool = False, tool: bool = False) -> World:
    """Add an object below `parent` at `pose` (relative to any frame; default: the parent's origin)."""
    _check_name(name, "object")
    if name in world:
        raise WorldError(f"object '{name}' already exists in {world.path}")
    if parent not in world:
        raise WorldError(f"no parent '{parent}' in {world.path}")
    local = readable_angles(_relative_to(world, pose, parent)) if pose is not None else Pose(0, 0, 0, frame=parent)
    attributes = [("parent", parent)] if parent != WORLD else []
    attributes.append(("pose", format_pose(local)))
    attributes += [("online_frame", "true")] if online_frame else []
    attributes += [("tool", "true")] if tool else []
    return world._reloaded(apply(world.dump(), [add_object(world.parsed, name, attributes)]))


def with_soft(world: World, owner: str, key: str, value: SoftValue) -> World:
    """Set a soft attribute (program state such as a pallet's next row)."""
    _check_name(key, "soft attribute")
    world.object(owner)
    return world._reloaded(apply(world.dump(), [set_entry(world.parsed, owner, "soft", key, format_soft(value))]))


def affix(world: World, name: str, to: str) -> World:
    """AFFIX: hang `name` (with its children) below `to`, keeping its world pose; it then moves with `to`."""
    world.object(name)
    if to not in world:
        raise WorldError(f"no object '{to}' to affix '{name}' to")
    if to == name or to in world.descendants(name):
        raise WorldError(f"cannot affix '{name}' to '{to}': '{to}' hangs below '{name}'")
    local = readable_angles(world.relative_pose(name, to), world.object(name).pose)
    patches = [set_attribute(world.parsed, name, "parent", to), set_attribute(world.parsed, name, "pose", format_pose(local))]
    return world._reloaded(apply(world.dump(), patches))


def unfix(world: World, name: str) -> World:
    """UNFIX: detach `name` from what it hangs on; it stays where it is, relative to the world."""
    return affix(world, name, WORLD)
