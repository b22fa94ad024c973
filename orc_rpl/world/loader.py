"""Reading a world file: YAML nodes to world objects, with every mistake reported at its file, line and column."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from functools import cached_property

from orc_rpl.errors import Diagnostic, SourceError
from orc_rpl.syntax.bulk import paused_gc
from orc_rpl.world.axes import read_axis
from orc_rpl.world.objects import FLANGE, NAME_RE, PREDEFINED, ROBOT as ROBOT_NAME, ModelAttributes, PathAttribute, Position, RobotEntry, WorldObject
from orc_rpl.world.pose import WORLD, Pose
from orc_rpl.world.source import MappingNode, Node, ScalarNode, SequenceNode, SourceText, did_you_mean
from orc_rpl.syntax.units import ANGLE, LENGTH, Quantity, magnitude
from orc_rpl.world.values import BadValue, read_colour, read_lengths, read_number, read_pose, read_soft

TOP_KEYS = ("robot", "world")
ROBOT_KEYS = ("model", "pose", "parent")
OBJECT_KEYS = ("parent", "pose", "online_frame", "tool", "work", "model", "model_key", "frames", "paths", "spatial", "soft", "axis")
MODEL_KEYS = ("geometry", "size", "colour", "mesh", "offset")
#: Geometry kinds and how many sizes each takes (a mesh takes its size from the mesh file).
GEOMETRIES = {"box": 3, "cylinder": 2, "sphere": 1, "mesh": 0}


@dataclass(frozen=True)
class Parsed:
    """A checked world file: its text and objects in file order; its YAML nodes (for exact edits) when asked for.

    The nodes are composed again from the text on first use and kept from then on: a large world has a quarter of a
    million of them, which only an edit needs, and dropped right after reading they cost neither memory nor the
    garbage collector's time (an `orc check --world` never asks for them).
    """

    src: SourceText
    robot: RobotEntry | None
    objects: tuple[WorldObject, ...]

    @cached_property
    def root(self) -> MappingNode | None:
        """The file's top-level mapping node."""
        return self.src.compose()  # type: ignore[return-value]

    @cached_property
    def object_nodes(self) -> dict[str, tuple[ScalarNode, MappingNode]]:
        """name -> (key node, attribute mapping) of every object; nodes compare by identity."""
        root = self.root
        world = next((value for key, value in root.value if key.value == "world"), None) if root is not None else None
        if not isinstance(world, MappingNode):  # `world:` with nothing under it yet
            return {}
        return {key.value: (key, value) for key, value in world.value}


def parse_world(text: str, path: str = "<world>") -> Parsed:
    """Read and check a world file's text; raise SourceError listing every problem found."""
    with paused_gc():  # thousands of objects and tens of thousands of nodes: see paused_gc
        return _Reader(SourceText(text, path)).read()


class _Reader:
    """One pass over the nodes, collecting diagnostics rather than stopping at the first."""

    def __init__(self, src: SourceText) -> None:
        self.src = src
        self.diags: list[Diagnostic] = []
        self.robot_parent_node: Node | None = None
        self.axis_refs: list[tuple[ScalarNode, Node, object]] = []   #: positions' axis values, checked at the end

    def bad(self, node: Node | None, message: str, hint: str = "") -> None:
        self.diags.append(self.src.diagnostic(node, message, hint))

    def read(self) -> Parsed:
        root = self.src.compose()
        robot, objects, nodes = None, [], {}
        if root is not None and not isinstance(root, MappingNode):
            raise self.src.not_a_world()
        if root is not None and not any(getattr(key, "value", None) in TOP_KEYS for key, _ in root.value):
            raise self.src.not_a_world()  # a mapping, but of something else: its lines are not ours to print
        if root is not None:
            if "&" in self.src.text:  # an anchor needs an '&': without one there is nothing to look for
                self.check_no_anchors(root)
            top = self.mapping(root, TOP_KEYS, "top-level key")
            if "robot" in top:
                robot = self.robot(top["robot"][1])
            if "world" in top:
                world_node = top["world"][1]
                if isinstance(world_node, ScalarNode) and world_node.tag.endswith(":null"):
                    world_node = None   # `world:` with nothing under it yet
                elif not self.is_block(world_node, "'world' is a block mapping of objects, one per name"):
                    world_node = None
                seen: dict[str, ScalarNode] = {}
                for key, value in world_node.value if world_node is not None else ():
                    if not self.check_name(key, "object"):
                        continue
                    if key.value in seen:
                        self.bad(key, f"duplicate object name '{key.value}'", f"first defined at line {seen[key.value].start_mark.line + 1}")
                        continue
                    if key.value in PREDEFINED:
                        self.bad(key, f"'{key.value}' is predefined in every world; choose another object name")
                        continue
                    seen[key.value] = key
                    obj = self.object(key, value)
                    if obj is not None:
                        objects.append(obj)
                        nodes[obj.name] = (key, value)
        self.check_tree(objects, nodes)
        self.check_moving_frames(robot, objects, nodes)
        if self.diags:
            self.diags.sort(key=lambda d: (d.location.line, d.location.column))
            raise SourceError(self.diags, self.src.text)
        return Parsed(self.src, robot, tuple(objects))

    def check_no_anchors(self, node: Node, seen: set[int] | None = None) -> None:
        """Anchors share one node between places: an edit of one place would silently change the other."""
        seen = set() if seen is None else seen
        if id(node) in seen:
            return
        seen.add(id(node))
        if getattr(node, "anchor", None):
            self.bad(node, f"anchor '&{node.anchor}': world files do not use anchors and aliases", "write the value out at each place")
        children = node.value if isinstance(node, (MappingNode, SequenceNode)) else ()
        for child in children:
            for sub in child if isinstance(child, tuple) else (child,):
                self.check_no_anchors(sub, seen)

    def is_block(self, node: Node, message: str) -> bool:
        if isinstance(node, MappingNode) and not node.flow_style:
            return True
        self.bad(node, message)
        return False

    def check_name(self, key: Node, what: str) -> bool:
        if isinstance(key, ScalarNode) and NAME_RE.fullmatch(key.value):
            return True
        self.bad(key, f"bad {what} name '{getattr(key, 'value', '?')}'", "a name is a letter or '_' followed by letters, digits and '_'")
        return False

    def mapping(self, node: Node, allowed: tuple[str, ...], what: str) -> dict[str, tuple[ScalarNode, Node]]:
        """A mapping's entries by key; unknown and repeated keys are reported."""
        out: dict[str, tuple[ScalarNode, Node]] = {}
        for key, value in node.value:
            name = getattr(key, "value", None)
            if not isinstance(name, str) or name not in allowed:
                self.bad(key, f"unknown {what} '{name}'", did_you_mean(str(name), list(allowed)) or "allowed: " + ", ".join(allowed))
            elif name in out:
                self.bad(key, f"duplicate key '{name}'", f"first given at line {out[name][0].start_mark.line + 1}")
            else:
                out[name] = (key, value)
        return out

    def robot(self, node: Node) -> RobotEntry | None:
        if not self.is_block(node, "'robot' is a mapping with 'model' and 'pose'"):
            return None
        keys = self.mapping(node, ROBOT_KEYS, "robot key")
        if "model" not in keys or not isinstance(keys["model"][1], ScalarNode):
            self.bad(node, "the robot needs 'model: <name>' (a robot model in worlds/, such as irb2400)")
            return None
        parent = WORLD
        if "parent" in keys and self.check_name(keys["parent"][1], "parent"):
            parent = keys["parent"][1].value   # the base rides on a moving frame (a track)
        pose = self.pose(keys["pose"][1], parent) if "pose" in keys else Pose(0, 0, 0, frame=parent)
        self.robot_parent_node = keys.get("parent", (None, None))[1]
        return RobotEntry(keys["model"][1].value, pose or Pose(0, 0, 0, frame=parent), self.src.location(node), parent)

    def pose(self, node: Node, frame: str) -> Pose | None:
        try:
            return read_pose(node, frame)
        except BadValue as exc:
            self.diags.append(exc.diagnostic(self.src))
            return None

    def flag(self, node: Node, key: str) -> bool:
        if isinstance(node, ScalarNode) and node.tag.endswith(":bool"):
            return node.value.lower() in ("true", "yes", "on")
        self.bad(node, f"'{key}' is true or false")
        return False

    def object(self, key: ScalarNode, node: Node) -> WorldObject | None:
        name = key.value
        if not self.is_block(node, f"object '{name}' is a block mapping of its attributes (parent, pose, frames, ...)"):
            return None
        attrs = self.mapping(node, OBJECT_KEYS, "object attribute")
        parent = WORLD
        if "parent" in attrs:
            pnode = attrs["parent"][1]
            if self.check_name(pnode, "parent"):
                parent = pnode.value
        pose = self.pose(attrs["pose"][1], parent) if "pose" in attrs else Pose(0, 0, 0, frame=parent)
        online = self.flag(attrs["online_frame"][1], "online_frame") if "online_frame" in attrs else False
        tool = self.flag(attrs["tool"][1], "tool") if "tool" in attrs else False
        work = self.flag(attrs["work"][1], "work") if "work" in attrs else False
        if "model" in attrs and "model_key" in attrs:
            self.bad(attrs["model_key"][0], "an object has either 'model' (off-line) or 'model_key' (on-line), not both")
        model = self.model(attrs["model"][1]) if "model" in attrs else None
        model_key = None
        if "model_key" in attrs:
            knode = attrs["model_key"][1]
            model_key = knode.value if isinstance(knode, ScalarNode) else None
        self.check_attribute_names(name, attrs)
        frames = self.frames(name, attrs["frames"][1]) if "frames" in attrs else ()
        paths = self.paths(name, attrs["paths"][1], frames) if "paths" in attrs else ()
        soft = self.soft(attrs["soft"][1], "soft") if "soft" in attrs else ()
        spatial = self.soft(attrs["spatial"][1], "spatial") if "spatial" in attrs else ()
        axis = read_axis(attrs["axis"][1], self.bad) if "axis" in attrs else None
        return WorldObject(name, parent, pose or Pose(0, 0, 0, frame=parent), online, tool, model, model_key,
                           frames, paths, soft, spatial, self.src.location(key), work=work, axis=axis)

    def check_attribute_names(self, owner: str, attrs: dict[str, tuple[ScalarNode, Node]]) -> None:
        """`owner.name` must name one thing: a frame, a path, a spatial or a soft attribute."""
        seen: dict[str, tuple[str, int]] = {}
        for section in ("frames", "paths", "spatial", "soft"):
            node = attrs.get(section, (None, None))[1]
            for key, _ in node.value if isinstance(node, MappingNode) else ():
                name = getattr(key, "value", None)
                if name in seen and seen[name][0] != section:
                    first, line = seen[name]
                    self.bad(key, f"'{owner}.{name}' is defined twice, in {first} and in {section}", f"the first is at line {line}")
                seen.setdefault(name, (section, key.start_mark.line + 1))

    def entries(self, node: Node, what: str) -> list[tuple[ScalarNode, Node]]:
        """Named entries of frames/paths/soft (an empty value means none), names checked and unique."""
        if isinstance(node, ScalarNode) and node.tag.endswith(":null"):
            return []
        if not isinstance(node, MappingNode):
            self.bad(node, f"{what} is a mapping of names to values")
            return []
        out, seen = [], {}
        for key, value in node.value:
            if not self.check_name(key, what.rstrip("s")):
                continue
            if key.value in seen:
                self.bad(key, f"duplicate name '{key.value}' in {what}", f"first defined at line {seen[key.value] + 1}")
                continue
            seen[key.value] = key.start_mark.line
            out.append((key, value))
        return out

    def frames(self, owner: str, node: Node) -> tuple[Position, ...]:
        out = []
        for key, value in self.entries(node, "frames"):
            axes: tuple[tuple[str, float], ...] = ()
            if isinstance(value, SequenceNode) and len(value.value) == 7 and isinstance(value.value[6], MappingNode):
                # [x, y, z, a, b, c, {track: 200mm}]: a position carrying external-axis values
                axes = self.axis_values(value.value[6])
                value = type(value)(value.tag, value.value[:6], value.start_mark, value.end_mark, flow_style=value.flow_style)
            pose = self.pose(value, owner)
            if pose is not None:
                out.append(Position(key.value, dataclasses.replace(pose, axes=axes), self.src.location(key)))
        return tuple(out)

    def axis_values(self, node: MappingNode) -> tuple[tuple[str, float], ...]:
        """`{track: 200mm, turn: 90deg}`: the external-axis values of a position, in the order written (checked
        against the moving frames once every object is read)."""
        out = []
        for key, value in node.value:
            if not self.check_name(key, "axis"):
                continue
            try:
                number = read_number(value, f"the value of axis '{key.value}'")
            except BadValue as exc:
                self.diags.append(exc.diagnostic(self.src))
                continue
            out.append((key.value, float(magnitude(number))))
            self.axis_refs.append((key, value, number))
        return tuple(out)

    def paths(self, owner: str, node: Node, frames: tuple[Position, ...]) -> tuple[PathAttribute, ...]:
        by_name = {f.name: f for f in frames}
        out = []
        for key, value in self.entries(node, "paths"):
            if not isinstance(value, SequenceNode):
                self.bad(value, "a path is a list of frame names and poses")
                continue
            points, refs = [], []
            for item in value.value:
                if isinstance(item, ScalarNode):
                    if item.value not in by_name:
                        self.bad(item, f"'{owner}' has no frame '{item.value}'", did_you_mean(item.value, list(by_name)))
                        continue
                    points.append(by_name[item.value].pose)
                    refs.append(item.value)
                else:
                    pose = self.pose(item, owner)
                    if pose is not None:
                        points.append(pose)
                        refs.append(None)
            out.append(PathAttribute(key.value, tuple(points), tuple(refs), self.src.location(key)))
        return tuple(out)

    def soft(self, node: Node, what: str) -> tuple:
        out = []
        for key, value in self.entries(node, what):
            try:
                out.append((key.value, read_soft(value)))
            except BadValue as exc:
                self.diags.append(exc.diagnostic(self.src))
        return tuple(out)

    def model(self, node: Node) -> ModelAttributes | None:
        if not isinstance(node, MappingNode):
            self.bad(node, "'model' is a mapping: geometry, size, colour, mesh")
            return None
        keys = self.mapping(node, MODEL_KEYS, "model attribute")
        geometry = keys["geometry"][1].value if "geometry" in keys and isinstance(keys["geometry"][1], ScalarNode) else None
        if geometry is not None and geometry not in GEOMETRIES:
            self.bad(keys["geometry"][1], f"unknown geometry '{geometry}'", did_you_mean(geometry, list(GEOMETRIES)) or "box, cylinder, sphere or mesh")
        size: tuple[float, ...] = ()
        if "size" in keys:
            try:
                size = read_lengths(keys["size"][1], "size")
            except BadValue as exc:
                self.diags.append(exc.diagnostic(self.src))
            wanted = GEOMETRIES.get(geometry or "", 0)
            if size and wanted and len(size) != wanted:
                self.bad(keys["size"][1], f"a {geometry} has {wanted} size value{'s' if wanted > 1 else ''}, got {len(size)}")
        colour = None
        if "colour" in keys:
            cnode = keys["colour"][1]
            try:
                colour = cnode.value if isinstance(cnode, ScalarNode) else read_colour(cnode)
            except BadValue as exc:
                self.diags.append(exc.diagnostic(self.src))
        mesh = keys["mesh"][1].value if "mesh" in keys and isinstance(keys["mesh"][1], ScalarNode) else None
        if geometry == "mesh" and mesh is None:
            self.bad(node, "geometry 'mesh' needs 'mesh: <file>'")
        offset = self.pose(keys["offset"][1], "model") if "offset" in keys else None
        return ModelAttributes(geometry, size, colour, mesh, offset)

    def check_tree(self, objects: list[WorldObject], nodes: dict[str, tuple[ScalarNode, MappingNode]]) -> None:
        """Parents exist, parent links have no cycle, tools hang below the flange."""
        by_name = {o.name: o for o in objects}
        known = set(by_name) | set(PREDEFINED)

        def parent_node(name: str) -> Node:
            entry = next((v for k, v in nodes[name][1].value if getattr(k, "value", None) == "parent"), None)
            return entry if entry is not None else nodes[name][0]

        for obj in objects:
            if obj.parent not in known:
                self.bad(parent_node(obj.name), f"unknown parent '{obj.parent}' of '{obj.name}'", did_you_mean(obj.parent, known))
        reported: set[str] = set()
        for obj in objects:
            chain, name = [], obj.name
            while name in by_name and name not in chain:
                chain.append(name)
                name = by_name[name].parent
            if name in chain and name not in reported:
                cycle = chain[chain.index(name):]
                reported.update(cycle)
                first = min(cycle, key=lambda n: nodes[n][0].start_mark.line)
                i = cycle.index(first)
                ring = cycle[i:] + cycle[:i] + [first]
                self.bad(parent_node(first), "cycle in parents: " + " -> ".join(ring), "an object cannot be its own ancestor")
        for obj in objects:
            if not obj.tool:
                continue
            chain, name = set(), obj.parent
            while name in by_name and name not in chain:
                chain.add(name)
                name = by_name[name].parent
            if name != FLANGE and name in PREDEFINED:
                tool_key = next(k for k, _ in nodes[obj.name][1].value if getattr(k, "value", None) == "tool")
                self.bad(tool_key, f"tool '{obj.name}' is not mounted on the flange", "give it (or its holder) 'parent: flange'")

    def check_moving_frames(self, robot: RobotEntry | None, objects: list[WorldObject],
                            nodes: dict[str, tuple[ScalarNode, MappingNode]]) -> None:
        """The robot rides on an object of the world, not inside itself; no moving frame hangs below the flange."""
        by_name = {o.name: o for o in objects}
        if robot is not None and robot.parent != WORLD:
            node = self.robot_parent_node
            chain, name = [], robot.parent
            while name in by_name and name not in chain:
                chain.append(name)
                name = by_name[name].parent
            if robot.parent not in by_name:
                self.bad(node, f"unknown parent '{robot.parent}' of the robot",
                         did_you_mean(robot.parent, list(by_name)) or "the robot rides on an object of the world (a track)")
            elif name in (ROBOT_NAME, FLANGE):
                self.bad(node, f"the robot cannot ride on '{robot.parent}', which hangs on the robot itself")
        axes = {o.name: o.axis for o in objects if o.axis is not None and o.axis.joint != "conveyor"}
        for key, value, number in self.axis_refs:
            axis = axes.get(key.value)
            if axis is None:
                self.bad(key, f"unknown external axis '{key.value}'",
                         did_you_mean(key.value, list(axes)) or "an axis is an object with 'axis:' (not a conveyor)")
            elif isinstance(number, Quantity) and number.dim != (ANGLE if axis.rotary else LENGTH):
                self.bad(value, f"axis '{key.value}' is {'rotary' if axis.rotary else 'linear'}: its value is "
                         f"{'an angle' if axis.rotary else 'a length'}, got '{value.value}'")
        for obj in objects:
            if obj.axis is None:
                continue
            chain, name = [], obj.parent
            while name in by_name and name not in chain:
                chain.append(name)
                name = by_name[name].parent
            if name in (ROBOT_NAME, FLANGE):
                axis_key = next(k for k, _ in nodes[obj.name][1].value if getattr(k, "value", None) == "axis")
                self.bad(axis_key, f"'{obj.name}' hangs on the robot: a moving frame of the cell stands in the cell",
                         "external axes (tracks, positioners, conveyors) hang on 'world' or on other objects of the cell")
