"""The World: an immutable, checked world file with the queries the transformation and the executive ask."""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np

from orc_rpl.atomic import write_text_atomic
from orc_rpl.syntax.reading import read_text
from orc_rpl.world import changes
from orc_rpl.world.loader import Parsed, parse_world
from orc_rpl.world.objects import (DOTTED_RE, FLANGE, PREDEFINED, ROBOT, ModelAttributes, OnlineFrame, PathAttribute,
                                   Position, RobotEntry, WorldError, WorldObject)
from orc_rpl.world.pose import WORLD, Pose
from orc_rpl.world.source import did_you_mean

Lookup = WorldObject | Position | PathAttribute | Pose | object


def load_world(path: str | os.PathLike[str]) -> World:
    """Read and check a world file; a mistake raises SourceError with file:line:col, the line and a caret."""
    return World(parse_world(read_text(path, "world model"), os.fspath(path)))


def loads_world(text: str, path: str = "<world>") -> World:
    """A world from text (`path` names it in messages)."""
    return World(parse_world(text, path))


@dataclass(frozen=True)
class World:
    """A world model: the exact file text, its objects, and at run time the flange pose."""

    parsed: Parsed = field(repr=False)
    flange_pose: Pose | None = None        #: flange relative to the robot base; known only at run time
    #: moving frames' axis values (m or rad) by object name, run-time state; an axis not named is at its home
    axis_values: tuple[tuple[str, float], ...] = ()

    # -- the file ---------------------------------------------------------------------------------
    @property
    def path(self) -> str:
        return self.parsed.src.path

    def dump(self) -> str:
        """The world file's text: byte for byte what was loaded, plus any edits."""
        return self.parsed.src.text

    def save(self, path: str | os.PathLike[str] | None = None) -> None:
        """Write the file atomically: a temporary file in the same folder, then os.replace."""
        write_text_atomic(os.fspath(path if path is not None else self.path), self.dump())

    def _reloaded(self, text: str) -> World:
        return World(parse_world(text, self.path), self.flange_pose, self.axis_values)

    def with_flange(self, pose: Pose) -> World:
        """The same world with the flange at `pose` relative to the robot base (run-time state, never saved)."""
        return World(self.parsed, pose, self.axis_values)

    # -- moving frames ------------------------------------------------------------------------------
    def moving_frames(self) -> tuple[str, ...]:
        """Objects an external axis or a conveyor moves, in file order."""
        return tuple(o.name for o in self.objects if o.axis is not None)

    def axis_value(self, name: str) -> float:
        """Where a moving frame's axis is (m or rad): the value given to with_axes, else its home."""
        axis = self.object(name).axis
        if axis is None:
            raise WorldError(f"'{name}' is not a moving frame (it has no 'axis:')")
        return dict(self.axis_values).get(name, axis.home_si)

    def with_axes(self, values: Mapping[str, float]) -> World:
        """The same world with moving frames at the given axis values (run-time state, never saved)."""
        current = dict(self.axis_values)
        for name, value in values.items():
            axis = self.object(name).axis
            if axis is None:
                hint = did_you_mean(name, list(self.moving_frames()))
                raise WorldError(f"'{name}' is not a moving frame (it has no 'axis:')" + (f"; {hint}" if hint else ""))
            why = axis.clamp_message(float(value))
            if why is not None:
                raise WorldError(f"axis '{name}': {why}")
            current[name] = float(value)
        return World(self.parsed, self.flange_pose, tuple(sorted(current.items())))

    # -- objects and names ------------------------------------------------------------------------
    @property
    def robot(self) -> RobotEntry | None:
        return self.parsed.robot

    @property
    def objects(self) -> tuple[WorldObject, ...]:
        """Every object in file order."""
        return self.parsed.objects

    def _by_name(self) -> dict[str, WorldObject]:
        cache = self.__dict__.get("_cache")
        if cache is None:
            cache = {o.name: o for o in self.parsed.objects}
            object.__setattr__(self, "_cache", cache)
        return cache

    def __contains__(self, name: str) -> bool:
        return name in self._by_name() or name in PREDEFINED

    def object(self, name: str) -> WorldObject:
        """An object by name; an unknown name raises WorldError with a suggestion."""
        obj = self._by_name().get(name)
        if obj is None:
            hint = did_you_mean(name, list(self._by_name()))
            raise WorldError(f"no object '{name}' in {self.path}" + (f"; {hint}" if hint else ""))
        return obj

    def parent(self, name: str) -> str | None:
        """The parent of an object (`world` has none)."""
        if name == WORLD:
            return None
        if name == ROBOT:
            return self.robot.parent if self.robot is not None else WORLD
        if name == FLANGE:
            return ROBOT
        return self.object(name).parent

    def ancestors(self, name: str) -> tuple[str, ...]:
        """Parent, grandparent, ... up to `world`."""
        out, p = [], self.parent(name)
        while p is not None:
            out.append(p)
            p = self.parent(p)
        return tuple(out)

    def children(self, name: str) -> tuple[str, ...]:
        """What hangs directly on `name`: objects in file order (and `robot` on world, `flange` on robot)."""
        fixed = {ROBOT: (FLANGE,)}.get(name, ())
        if name == self.parent(ROBOT):
            fixed = (ROBOT,)
        return fixed + tuple(o.name for o in self.objects if o.parent == name)

    def descendants(self, name: str) -> tuple[str, ...]:
        """Every object below `name`, depth first in file order."""
        out: list[str] = []
        for child in self.children(name):
            out += [child, *self.descendants(child)]
        return tuple(out)

    def lookup(self, dotted: str) -> Lookup:
        """`obj`, `obj.frame`, `obj.path` or `obj.path[i]` (from 1): the object, Position, PathAttribute or Pose."""
        m = DOTTED_RE.fullmatch(dotted)
        if m is None:
            raise WorldError(f"'{dotted}' is not a world name (object, object.frame or object.path[i])")
        owner, attr, index = m.groups()
        obj = self.object(owner)
        if attr is None:
            return obj
        frame, path = obj.frame(attr), obj.path(attr)
        if index is None and frame is not None:
            return frame
        if index is None and path is None and (attr in obj.soft or attr in obj.spatial):
            return {**obj.spatial, **obj.soft}[attr]
        if path is None:
            names = [f.name for f in obj.frames] + [p.name for p in obj.paths] + [*obj.soft, *obj.spatial]
            hint = did_you_mean(attr, names)
            raise WorldError(f"'{owner}' has no frame, path or attribute '{attr}'" + (f"; {hint}" if hint else ""))
        if index is None:
            return path
        i = int(index)
        if not 1 <= i <= len(path.points):
            raise WorldError(f"'{dotted}': index {i} is outside 1..{len(path.points)}")
        return path.points[i - 1]

    # -- poses --------------------------------------------------------------------------------------
    def _local(self, name: str) -> np.ndarray:
        """The transform of a tree node relative to its parent."""
        if name == ROBOT:
            return self.robot.pose.matrix() if self.robot else np.eye(4)
        if name == FLANGE:
            if self.flange_pose is None:
                raise WorldError("the flange pose is known only at run time (World.with_flange)")
            return self.flange_pose.matrix()
        obj = self.object(name)
        if obj.axis is None:
            return obj.pose.matrix()
        return obj.pose.matrix() @ obj.axis.matrix(self.axis_value(name))

    def _node_and_offset(self, dotted: str) -> tuple[str, np.ndarray]:
        """The tree node a name hangs on and its transform relative to that node."""
        if dotted in PREDEFINED:
            return dotted, np.eye(4)
        found = self.lookup(dotted)
        owner = dotted.split(".", 1)[0]
        if isinstance(found, WorldObject):
            return owner, np.eye(4)
        if isinstance(found, PathAttribute):
            raise WorldError(f"'{dotted}' is a path of {len(found.points)} positions; name one as {dotted}[i]")
        if isinstance(found, Position):
            return owner, found.pose.matrix()
        if isinstance(found, Pose):
            return owner, found.matrix()
        raise WorldError(f"'{dotted}' is an attribute value, not a position")

    def _down_from(self, ancestor: str, name: str) -> np.ndarray:
        """Transform of tree node `name` relative to its ancestor (or itself)."""
        t, node = np.eye(4), name
        while node != ancestor:
            t = self._local(node) @ t
            node = self.parent(node)
        return t

    def relative_pose(self, dotted: str, frame: str = WORLD) -> Pose:
        """Pose of an object, frame or path element relative to any object (through their lowest common ancestor)."""
        node, offset = self._node_and_offset(dotted)
        ref, ref_offset = self._node_and_offset(frame)
        up = {node, *self.ancestors(node)}
        common = ref if ref in up else next(a for a in self.ancestors(ref) if a in up)
        t_node = self._down_from(common, node) @ offset
        t_ref = self._down_from(common, ref) @ ref_offset
        return Pose.from_matrix(np.linalg.inv(t_ref) @ t_node, frame)

    def world_pose(self, dotted: str) -> Pose:
        """Pose in world coordinates (composition up the tree)."""
        return self.relative_pose(dotted, WORLD)

    # -- on-line frames and tools ------------------------------------------------------------------
    def online_frame_of(self, dotted: str) -> str:
        """The on-line frame a name's numbers are taught in: the nearest tagged owner of a frame, or tagged proper ancestor of an object."""
        node, _ = self._node_and_offset(dotted)
        start = (node,) if "." in dotted else ()
        for name in start + self.ancestors(node):
            if name not in PREDEFINED and self.object(name).online_frame:
                return name
        return WORLD

    def online_pose(self, dotted: str) -> Pose:
        """Pose relative to its on-line frame (what `POS p = POSE(...) IN frame` holds)."""
        return self.relative_pose(dotted, self.online_frame_of(dotted))

    def online_frames(self) -> tuple[OnlineFrame, ...]:
        """Every tagged on-line frame, parents before children, with its enclosing on-line frame."""
        out = []
        for name in self.descendants(WORLD):
            if name not in PREDEFINED and self.object(name).online_frame:
                outer = self.online_frame_of(name)
                out.append(OnlineFrame(name, outer, self.relative_pose(name, outer)))
        return tuple(out)

    def positions(self) -> tuple[str, ...]:
        """Dotted names of every named frame and path element, objects in file order (what programs move to)."""
        out = []
        for obj in self.objects:
            out += [f"{obj.name}.{f.name}" for f in obj.frames]
            out += [f"{obj.name}.{p.name}[{i}]" for p in obj.paths for i in range(1, len(p.points) + 1)]
        return tuple(out)

    def robot_model_file(self) -> str | None:
        """The robot's MJCF file: `<model>.xml` next to the world file (worlds/irb2400.xml)."""
        if self.robot is None:
            return None
        return os.path.join(os.path.dirname(self.path), f"{self.robot.model}.xml")

    def tools(self) -> tuple[str, ...]:
        """Objects tagged as tools, in file order."""
        return tuple(o.name for o in self.objects if o.tool)

    def tool_chain(self, tool: str) -> tuple[str, ...]:
        """The objects from the flange down to a tool (`holder`, `grinder`): ARM*Holder*Grinder without ARM."""
        up = self.ancestors(tool)
        if FLANGE not in up:
            raise WorldError(f"'{tool}' is not mounted on the flange")
        return tuple(reversed(up[: up.index(FLANGE)])) + (tool,)

    def tool_pose(self, tool: str) -> Pose:
        """The tool chain collapsed into one TCP pose relative to the flange (`TOOL grinder = POSE(...)`)."""
        self.tool_chain(tool)
        return self.relative_pose(tool, FLANGE)

    # -- attributes ---------------------------------------------------------------------------------
    def model(self, name: str) -> ModelAttributes | None:
        """Model attributes (geometry, colour, mesh) of an object, off-line only."""
        return self.object(name).model

    def soft(self, name: str) -> Mapping[str, object]:
        """Soft attributes (program state) of an object."""
        return self.object(name).soft

    # -- changes (each returns a new World; the file text changes only where the change is) ---------
    def with_frame(self, owner: str, name: str, pose: Pose) -> World:
        """Add or change the frame `owner.name` (teach / touch-up); `pose` may be relative to any frame."""
        return changes.with_frame(self, owner, name, pose)

    def with_pose(self, name: str, pose: Pose) -> World:
        """Move an object, its children with it; `pose` may be relative to any frame."""
        return changes.with_pose(self, name, pose)

    def with_object(self, name: str, parent: str = WORLD, pose: Pose | None = None, *,
                    online_frame: bool = False, tool: bool = False) -> World:
        """Add an object below `parent`."""
        return changes.with_object(self, name, parent, pose, online_frame=online_frame, tool=tool)

    def with_soft(self, owner: str, key: str, value: object) -> World:
        """Set a soft attribute of an object."""
        return changes.with_soft(self, owner, key, value)  # type: ignore[arg-type]

    def affix(self, name: str, to: str) -> World:
        """AFFIX name TO to: keep its world pose, from now on move with `to`."""
        return changes.affix(self, name, to)

    def unfix(self, name: str) -> World:
        """UNFIX name: hang it on the world where it is."""
        return changes.unfix(self, name)
