"""The on-line declarations of the world entities a program uses (FRAME, TOOL, POS, PATH), made from the world and taken back into it."""

from __future__ import annotations

import dataclasses

from orc_rpl.syntax import nodes as n
from orc_rpl.world import WORLD, World
from orc_rpl.world.editing import apply, set_entry
from orc_rpl.world.values import format_pose
from orc_rpl.transform.job import Job, TransformError
from orc_rpl.transform.naming import FRAME, OBJECT, Names, name_world
from orc_rpl.transform.treemap import declared_names, references
from orc_rpl.transform.poses import rotary_axes, frame_pose, literal_path, literal_pose, object_pose, path_poses, pose_literal, tool_pose

DECLARED_KINDS = ("FRAME", "TOOL", "POS", "PATH")


def _in(frame: str, names: Names) -> n.Name | None:
    return None if frame == WORLD else n.Name(names.online[frame])


def declaration_for(world: World, names: Names, dotted: str) -> n.Declaration:
    """The on-line declaration of one entity, numbers relative to its on-line frame."""
    name = n.Name(names.online[dotted])
    kind = names.kinds[dotted]
    if kind == OBJECT:
        obj = world.object(dotted)
        if obj.tool:
            return n.Declaration("TOOL", name, pose_literal(tool_pose(world, dotted)))
        pose, frame = object_pose(world, dotted)
        return n.Declaration("FRAME" if obj.online_frame else "POS", name, pose_literal(pose), _in(frame, names))
    if kind == FRAME:
        pose, frame = frame_pose(world, dotted)
        return n.Declaration("POS", name, pose_literal(pose, rotary_axes(world) if pose.axes else frozenset()), _in(frame, names))
    poses, frame = path_poses(world, dotted)
    return n.Declaration("PATH", name, n.ListExpr(tuple(pose_literal(p) for p in poses)), _in(frame, names))


def leading_comments(body: n.Body) -> int:
    """How many comment lines open the program (the generated declarations go right after them)."""
    i = 0
    while i < len(body) and isinstance(body[i], n.Comment):
        i += 1
    return i


def _insert(job: Job, declarations: list[n.Declaration]) -> Job:
    body = job.program.body
    at = leading_comments(body)
    program = dataclasses.replace(job.program, body=body[:at] + tuple(declarations) + body[at:])
    return dataclasses.replace(job, program=program)


def _objects_used(job: Job, predicate) -> list[str]:  # type: ignore[no-untyped-def]
    names = job.names
    assert names is not None
    return [d for d in job.used if names.kinds[d] == OBJECT and predicate(job.world.object(d))]


def declare_positions(job: Job) -> Job:
    """`POS pos1 = POSE(...) IN base_plate` and `PATH` for every position and path used, in order of first use."""
    names = job.names
    assert names is not None
    used = [d for d in job.used if names.kinds[d] != OBJECT or not (job.world.object(d).tool or job.world.object(d).online_frame)]
    return _insert(job, [declaration_for(job.world, names, d) for d in used])


def collapse_tools(job: Job) -> Job:
    """`TOOL grinder = POSE(...)`: each tool chain ARM*holder*grinder collapsed into the one tool frame the on-line program needs."""
    names = job.names
    assert names is not None
    return _insert(job, [declaration_for(job.world, names, d) for d in _objects_used(job, lambda o: o.tool)])


def online_frames_in_order(world: World) -> list[str]:
    """The tagged on-line frames, depth first from the world in file order: outer frames before the frames inside them."""
    children: dict[str, list[str]] = {WORLD: ["robot"], "robot": ["flange"]}
    for obj in world.objects:
        children.setdefault(obj.parent, []).append(obj.name)
    out: list[str] = []
    stack = list(reversed(children[WORLD]))
    while stack:
        name = stack.pop()
        if name not in ("robot", "flange") and world.object(name).online_frame:
            out.append(name)
        stack.extend(reversed(children.get(name, [])))
    return out


def declare_frames(job: Job) -> Job:
    """`FRAME base_plate = POSE(...)` for every on-line frame a used position needs, outer frames first."""
    names = job.names
    assert names is not None
    needed = {f for chain in job.chains.values() for f in chain} | set(_objects_used(job, lambda o: o.online_frame))
    for frame in list(needed):
        needed |= set(job.world.ancestors(frame)) & {o.name for o in job.world.objects if o.online_frame}
    ordered = [f for f in online_frames_in_order(job.world) if f in needed]
    used = dict.fromkeys(job.used)
    used.update(dict.fromkeys(ordered))
    job = dataclasses.replace(job, used=tuple(used))
    return _insert(job, [declaration_for(job.world, names, f) for f in ordered])


# ---- the inverse: declarations back into the world ---------------------------------------------------------------


def absorbable(stmt: n.Statement, new: bool = False) -> bool:
    """A declaration the world can hold: a literal pose or a list of them, and no comment (a new path needs an on-line frame)."""
    if not isinstance(stmt, n.Declaration) or stmt.kind not in DECLARED_KINDS or stmt.comment is not None:
        return False
    if stmt.kind == "PATH":
        return (stmt.frame is not None or not new) and literal_path(stmt.value) is not None
    return literal_pose(stmt.value) is not None


def _with_path(world: World, owner: str, name: str, poses) -> World:  # type: ignore[no-untyped-def]
    text = "[" + ", ".join(format_pose(p) for p in poses) + "]"
    return world._reloaded(apply(world.dump(), [set_entry(world.parsed, owner, "paths", name, text)]))


def absorb(world: World, names: Names, stmt: n.Declaration) -> tuple[World, str]:
    """The world with one on-line declaration taken in (a taught, touched-up or unchanged entity), and the entity."""
    frame = names.entity.get(stmt.frame.id, stmt.frame.id) if stmt.frame is not None else WORLD
    if frame != WORLD and frame not in world._by_name():
        raise TransformError(f"'{stmt.name.id}' is relative to '{frame}', which is not in {world.path}")
    dotted = names.entity.get(stmt.name.id)
    if dotted is not None:
        if declaration_for(world, names, dotted) == dataclasses.replace(stmt, comment=None):
            return world, dotted
        return _changed(world, names, dotted, stmt, frame), dotted
    if stmt.kind == "PATH":
        if frame == WORLD:
            raise TransformError(f"path '{stmt.name.id}' is not relative to an on-line frame; the world model cannot hold it")
        return _with_path(world, frame, stmt.name.id, literal_path(stmt.value, frame)), f"{frame}.{stmt.name.id}"
    pose = literal_pose(stmt.value, frame)
    assert pose is not None
    if stmt.kind == "FRAME":
        return world.with_object(stmt.name.id, frame, pose, online_frame=True), stmt.name.id
    if stmt.kind == "TOOL":
        return world.with_object(stmt.name.id, "flange", pose.with_frame("flange"), tool=True), stmt.name.id
    if frame != WORLD:
        return world.with_frame(frame, stmt.name.id, pose), f"{frame}.{stmt.name.id}"
    return world.with_object(stmt.name.id, WORLD, pose), stmt.name.id


def _changed(world: World, names: Names, dotted: str, stmt: n.Declaration, frame: str) -> World:
    """A declaration edited on-line: the entity's numbers change in the world."""
    kind = names.kinds[dotted]
    if stmt.kind == "PATH" or kind not in (OBJECT, FRAME):
        raise TransformError(f"path '{stmt.name.id}' was changed on-line; edit '{dotted}' in the world model")
    pose = literal_pose(stmt.value, "flange" if stmt.kind == "TOOL" else frame)
    assert pose is not None
    if kind == FRAME:
        owner, attr = dotted.split(".")
        return world.with_frame(owner, attr, pose)
    return world.with_pose(dotted, pose)


def absorb_declarations(job: Job) -> Job:
    """Top-level declarations of the world's entities leave the program: unchanged ones vanish, touched-up and taught ones
    change the world."""
    world, names = job.world, job.named().names
    assert names is not None
    kept: list[n.Statement] = []
    used: dict[str, None] = dict.fromkeys(job.used)
    for stmt in job.program.body:
        take = False
        if absorbable(stmt):
            known = stmt.name.id in names.entity  # type: ignore[union-attr]
            taught = stmt.kind in ("POS", "PATH") and stmt.frame is not None and stmt.frame.id in names.entity  # type: ignore[union-attr]
            take = known or taught
        if not take:
            kept.append(stmt)
            continue
        world, dotted = absorb(world, names, stmt)  # type: ignore[arg-type]
        used.setdefault(dotted)
        if dotted not in names.online:
            names = name_world(world)
            if names.online.get(dotted) != stmt.name.id:  # type: ignore[union-attr]
                raise TransformError(f"'{stmt.name.id}' would be named '{names.online.get(dotted)}' on-line: a name clash in the world")
    program = dataclasses.replace(job.program, body=tuple(kept))
    # Given the world the program came from, a name it uses without declaring it is that world's entity too.
    own = declared_names(program)
    for expr in references(program):
        if isinstance(expr, n.Name) and expr.id in names.entity and expr.id not in own:
            used.setdefault(names.entity[expr.id])
    return dataclasses.replace(job, program=program, world=world, names=names, used=tuple(used))
