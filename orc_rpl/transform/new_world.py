"""A world model made from an on-line program's declarations (a program that was never off-line), written in one go."""

from __future__ import annotations

import dataclasses

from orc_rpl.syntax import nodes as n
from orc_rpl.world import WORLD, loads_world
from orc_rpl.world.objects import PREDEFINED
from orc_rpl.world.values import format_pose
from orc_rpl.transform.job import Job, TransformError
from orc_rpl.transform.poses import literal_path, literal_pose

#: The first lines of every world made from a program.
HEADER = "# The world model of an on-line program, made from its declarations by `orc convert`.\nworld:\n"


@dataclasses.dataclass
class _Object:
    """An object being written: its attribute lines, frames and paths."""

    lines: list[str]
    frames: list[str] = dataclasses.field(default_factory=list)
    paths: list[str] = dataclasses.field(default_factory=list)


def world_text(declarations: list[n.Declaration]) -> tuple[str, list[str]]:
    """The YAML text holding the declarations, and the entity (`base_plate.pos1`, `pos0`) of each.

    FRAME: a tagged object (below its IN frame); TOOL: an object on the flange; POS IN f: a frame of f; other POS: an
    object in the world; PATH IN f: a path of f. Poses are written as the world library writes them (mm, deg).
    """
    objects: dict[str, _Object] = {}
    entities: list[str] = []
    for stmt in declarations:
        name, frame = stmt.name.id, stmt.frame.id if stmt.frame is not None else WORLD
        if name in PREDEFINED or name in objects:
            raise TransformError(f"'{name}' cannot name an object of a world model")
        if frame != WORLD and frame not in objects:
            raise TransformError(f"'{name}' is relative to '{frame}', which is not a frame declared before it")
        if stmt.kind == "PATH":
            poses = literal_path(stmt.value)
            if frame == WORLD or poses is None:
                raise TransformError(f"path '{name}' needs an on-line frame to hang on")
            objects[frame].paths.append(f"      {name}: [{', '.join(format_pose(p) for p in poses)}]")
            entities.append(f"{frame}.{name}")
            continue
        pose = literal_pose(stmt.value)
        if pose is None:
            raise TransformError(f"'{name}' is not a literal pose")
        if stmt.kind == "POS" and frame != WORLD:
            objects[frame].frames.append(f"      {name}: {format_pose(pose)}")
            entities.append(f"{frame}.{name}")
            continue
        parent = "flange" if stmt.kind == "TOOL" else frame
        lines = ([f"    parent: {parent}"] if parent != WORLD else []) + [f"    pose: {format_pose(pose)}"]
        lines += ["    online_frame: true"] if stmt.kind == "FRAME" else ["    tool: true"] if stmt.kind == "TOOL" else []
        objects[name] = _Object(lines)
        entities.append(name)
    out = [HEADER]
    for name, obj in objects.items():
        out.append(f"  {name}:\n" + "".join(line + "\n" for line in obj.lines))
        if obj.frames:
            out.append("    frames:\n" + "".join(line + "\n" for line in obj.frames))
        if obj.paths:
            out.append("    paths:\n" + "".join(line + "\n" for line in obj.paths))
    return "".join(out), entities


def absorb_new(program: n.Program, chosen: frozenset[int], path: str = "<program>") -> Job:
    """The program without the chosen top-level declarations, and a new world holding them."""
    taken = [stmt for i, stmt in enumerate(program.body) if i in chosen]
    text, entities = world_text(taken)  # type: ignore[arg-type]
    kept = tuple(stmt for i, stmt in enumerate(program.body) if i not in chosen)
    return Job(dataclasses.replace(program, body=kept), loads_world(text, "<new world>"), path, used=tuple(entities)).named()
