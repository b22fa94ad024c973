"""World references in programs: `base_plate.pos1` <-> the on-line name `pos1`, and the checks of unknown world paths."""

from __future__ import annotations

import dataclasses
from types import MappingProxyType

from orc_rpl.errors import Diagnostic, Location
from orc_rpl.syntax import nodes as n
from orc_rpl.world import WORLD, World
from orc_rpl.world.objects import FLANGE, WorldObject
from orc_rpl.world.source import did_you_mean
from orc_rpl.transform.job import Job, TransformError
from orc_rpl.transform.naming import FRAME, OBJECT, PATH
from orc_rpl.transform.treemap import declared_names, map_references, references


def _object(world: World, name: str, shadowed: set[str]) -> WorldObject | None:
    if name in shadowed:
        return None
    return world._by_name().get(name)


def _attribute_kind(obj: WorldObject, attr: str) -> str | None:
    """FRAME, PATH, 'value' (soft or spatial attribute) or None."""
    if obj.frame(attr) is not None:
        return FRAME
    if obj.path(attr) is not None:
        return PATH
    if attr in obj.soft or attr in obj.spatial:
        return "value"
    return None


def _unknown(obj: WorldObject, attr: n.Name, world: World) -> tuple[str, str]:
    names = [f.name for f in obj.frames] + [p.name for p in obj.paths] + [*obj.soft, *obj.spatial]
    hint = did_you_mean(attr.id, names)
    return f"'{obj.name}' has no frame, path or attribute '{attr.id}' in {world.path}", hint


def _on_flange_not_tool(world: World, obj: WorldObject) -> bool:
    """An object carried by the robot (below the flange) that is not a tool nor inside one: a program cannot name it as
    a position (its pose is the flange's, known only at run time) and the transformation has no tool to make of it."""
    if obj.tool:
        return False
    chain = world.ancestors(obj.name)
    return FLANGE in chain and not any(name != FLANGE and world.object(name).tool for name in chain[:chain.index(FLANGE)])


def _carried(obj: WorldObject, world: World) -> tuple[str, str]:
    return (f"'{obj.name}' hangs on the flange in {world.path} but is not a tool: where it is is known only while the "
            "robot runs", f"mark it `tool: true` in {world.path} (a tool, or a part of one)")


def installed_names(program: n.Program) -> frozenset[str]:
    """Names the program INSTALLs equipment as: on a world tool (`install gripper as Gripper`), `gripper.Close` is a method."""
    return frozenset(node.name.id for stmt in program.body for node in stmt.walk() if isinstance(node, n.Install))


def world_diagnostics(program: n.Program, world: World, path: str) -> list[Diagnostic]:
    """Unknown world paths (`fixture.posX`) and path indices out of range, each at its line and column."""
    shadowed = declared_names(program)
    installed = installed_names(program)
    out: list[Diagnostic] = []
    reported: set[str] = set()
    for expr in references(program):
        if isinstance(expr, n.Name):
            obj = _object(world, expr.id, shadowed)
            if obj is not None and obj.name not in reported and _on_flange_not_tool(world, obj):
                reported.add(obj.name)   # once, at its first use
                span = expr.span
                out.append(Diagnostic(Location(path, span.line or 1, span.column or 1, span.end_line, span.end_column),
                                      *_carried(obj, world)))
        elif isinstance(expr, n.Field) and isinstance(expr.value, n.Name):
            obj = _object(world, expr.value.id, shadowed)
            if obj is not None and _attribute_kind(obj, expr.name.id) is None and obj.name not in installed:
                message, hint = _unknown(obj, expr.name, world)
                span = expr.name.span
                out.append(Diagnostic(Location(path, span.line or 1, span.column or 1, span.end_line, span.end_column),
                                      message, hint))
        elif isinstance(expr, n.Index) and isinstance(expr.value, n.Field) and isinstance(expr.value.value, n.Name):
            obj = _object(world, expr.value.value.id, shadowed)
            found = obj.path(expr.value.name.id) if obj is not None else None
            if found is not None and isinstance(expr.index, n.Number) and expr.index.text.isdigit():
                i = int(expr.index.text)
                if not 1 <= i <= len(found.points):
                    span = expr.index.span
                    out.append(Diagnostic(Location(path, span.line or 1, span.column or 1, span.end_line, span.end_column),
                                          f"index {i} is outside 1..{len(found.points)} of path '{obj.name}.{found.name}'"))  # type: ignore[union-attr]
    return out


def resolve_positions(job: Job) -> Job:
    """World paths in the program (`base_plate.pos1`, `pos0`, `grinder`) become on-line names; the entities used are recorded."""
    job = job.named()
    world, names = job.world, job.names
    assert names is not None
    shadowed = declared_names(job.program)
    installed = installed_names(job.program)
    used: dict[str, None] = dict.fromkeys(job.used)

    def use(dotted: str, like: n.Node) -> n.Name:
        used.setdefault(dotted)
        return n.Name(names.online[dotted], span=like.span)

    def resolve(expr: n.Expression) -> n.Expression | None:
        if isinstance(expr, n.Field) and isinstance(expr.value, n.Name):
            obj = _object(world, expr.value.id, shadowed)
            if obj is None:
                return None
            if _on_flange_not_tool(world, obj):
                raise job.error(expr.value, *_carried(obj, world))
            kind = _attribute_kind(obj, expr.name.id)
            if kind is None and obj.name in installed:
                return dataclasses.replace(expr, value=use(obj.name, expr.value))  # a method of the equipment on it
            if kind is None:
                message, hint = _unknown(obj, expr.name, world)
                raise job.error(expr.name, message, hint)
            if kind == "value":
                return expr  # soft and spatial attributes are read on-line from the reduced world
            return use(f"{obj.name}.{expr.name.id}", expr)
        if isinstance(expr, n.Name):
            obj = _object(world, expr.id, shadowed)
            if obj is not None and _on_flange_not_tool(world, obj):
                raise job.error(expr, *_carried(obj, world))
            if obj is not None:
                return use(obj.name, expr)
            if expr.id in names.entity and expr.id not in shadowed:
                # On-line this name would read as the world's entity: the inverse could not tell them apart.
                raise job.error(expr, f"'{expr.id}' is the on-line name of '{names.entity[expr.id]}' of the world model",
                                f"write {names.entity[expr.id]}, or declare '{expr.id}' in the program")
        return None

    program = map_references(job.program, resolve)
    for dotted in used:
        if names.online[dotted] in shadowed and names.online[dotted] != dotted:
            raise TransformError(f"'{dotted}' is named '{names.online[dotted]}' on-line, which the program uses for something else")
    return dataclasses.replace(job, program=program, used=tuple(used), chains=MappingProxyType(frame_chains(world, names, used)))


def online_frame(world: World, dotted: str) -> str:
    """The on-line frame an entity's numbers are relative to (objects: the nearest tagged proper ancestor)."""
    owner = dotted.split(".")[0]
    start = (owner,) if "." in dotted else ()
    for name in start + world.ancestors(owner):
        if name not in (WORLD, "robot", "flange") and (world.object(name).online_frame or world.object(name).axis is not None):
            return name  # a moving frame (a positioner's table) is an on-line frame the cell gives
    return WORLD


def chain_of(world: World, frame: str) -> tuple[str, ...]:
    """The on-line frames from the outermost down to `frame` (empty for world)."""
    chain: list[str] = []
    while frame != WORLD:
        chain.append(frame)
        if world.object(frame).axis is not None:
            break  # the cell knows where its moving frames are: their FRAME blocks need no outer ones
        frame = online_frame(world, frame)
    return tuple(reversed(chain))


def frame_chains(world: World, names, used) -> dict[str, tuple[str, ...]]:  # type: ignore[no-untyped-def]
    """On-line name -> FRAME nesting of each used position and path (tools and on-line frames are not positions)."""
    out = {}
    for dotted in used:
        if names.kinds[dotted] == OBJECT:
            obj = world.object(dotted)
            if obj.tool or obj.online_frame:
                continue
        out[names.online[dotted]] = chain_of(world, online_frame(world, dotted))
    return out


def unresolve_positions(job: Job) -> Job:
    """On-line names of world entities become world paths again (`pos1` -> `base_plate.pos1`)."""
    job = job.named()
    names = job.names
    assert names is not None
    own = declared_names(job.program)
    wanted = {names.online[d]: d for d in job.used if names.online[d] not in own}

    def back(expr: n.Expression) -> n.Expression | None:
        if isinstance(expr, n.Name) and expr.id in wanted:
            dotted = wanted[expr.id]
            if "." not in dotted:
                return n.Name(dotted, span=expr.span)
            owner, attr = dotted.split(".")
            return n.Field(n.Name(owner, span=expr.span), n.Name(attr, span=expr.span), span=expr.span)
        return None

    return dataclasses.replace(job, program=map_references(job.program, back))
