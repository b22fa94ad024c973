"""Hover: what a name is (its declaration as written, its frame, its value with units), a motion keyword, an attribute."""

from __future__ import annotations

import re

from orc_rpl.application.registry import Registry
from orc_rpl.lsp.analysis import Analysis
from orc_rpl.lsp.index import Definition, ProgramIndex, Target, name_at
from orc_rpl.lsp.words import attribute_detail, registry_keyword, type_with_unit
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.units import Quantity, parse_literal
from orc_rpl.transform.poses import literal_pose
from orc_rpl.world import WORLD, World, WorldError
from orc_rpl.world.pose import Pose, shown_pose

_WORD = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def word_at(line: str, character: int) -> str | None:
    """The word the 0-based character is on (or right after)."""
    for match in _WORD.finditer(line):
        if match.start() <= character <= match.end():
            return match.group(0)
    return None


def _code(text: str) -> str:
    return f"```\n{text}\n```"


def motion_hover(registry: Registry, word: str) -> str | None:
    """A motion keyword: its doc and every attribute it accepts with its type, unit and default."""
    spec = registry.motions.get(registry_keyword(word))
    if spec is None:
        return None
    lines = [f"**{spec.keyword}**: {spec.doc}", ""]
    lines += [f"* `{a.name}`: {attribute_detail(a)}. {a.doc}" for a in spec.attributes]
    return "\n".join(lines)


def _literal(stmt: n.Declaration) -> Pose | None:
    return literal_pose(stmt.value, stmt.frame.id if stmt.frame is not None else WORLD)


def _in_world(pose: Pose, index: ProgramIndex, line: int) -> Pose | None:
    """A literal pose carried through the literal FRAME declarations it is relative to; None when one is not literal."""
    for _ in range(32):  # deeper nesting than this is a cycle the checker reports
        if pose.frame == WORLD:
            return pose
        found = index.lookup(pose.frame, line)
        stmt = found.statement if found is not None else None
        outer = _literal(stmt) if isinstance(stmt, n.Declaration) and stmt.kind == "FRAME" else None
        if outer is None:
            return None
        pose = outer.compose(pose)
    return None


def _value_text(stmt: n.Declaration, index: ProgramIndex, line: int) -> str | None:
    """The declared value with units, for literals: a pose in the display convention (and in world), a number in SI."""
    pose = _literal(stmt)
    if pose is not None:
        text = shown_pose(pose).text()
        if pose.frame == WORLD:
            return text
        world = _in_world(pose, index, line)
        return f"{text} in {pose.frame}" + (f"\n\n= {shown_pose(world).text()} in world" if world is not None else "")
    if isinstance(stmt.value, n.Number):
        try:
            value = parse_literal(stmt.value.text)
        except (KeyError, ValueError):
            return None
        return str(value) if isinstance(value, Quantity) else None
    return None


def definition_hover(definition: Definition, lines: list[str], index: ProgramIndex) -> str:
    """A program's name: its kind, its declaration as written, its frame and value."""
    line = lines[definition.span.line - 1].strip() if 0 < definition.span.line <= len(lines) else definition.name
    where = f" of {definition.routine.kind} {definition.routine.name.id}" if definition.routine is not None else ""
    parts = [f"**{definition.name}**: {definition.kind}{where}, line {definition.span.line}", _code(line)]
    stmt = definition.statement
    if isinstance(stmt, n.Declaration):
        if stmt.kind in ("POS", "PATH", "FRAME"):
            parts.append(f"relative to `{stmt.frame.id if stmt.frame is not None else WORLD}`")
        value = _value_text(stmt, index, definition.span.line)
        if value is not None:
            parts.append(f"= {value}")
    return "\n\n".join(parts)


def world_hover(world: World, owner: str | None, name: str) -> str | None:
    """A world path (`base_plate.pos1`) or a world object: where it is, relative to its parent and in world."""
    if owner is None:
        if name not in {o.name for o in world.objects}:
            return None
        obj = world.object(name)
        head = f"**{name}**: world {'tool' if obj.tool else 'object'} on `{obj.parent}`" + (", on-line frame" if obj.online_frame else "")
        dotted, local = name, obj.pose
    else:
        if owner not in {o.name for o in world.objects}:
            return None
        obj = world.object(owner)
        frame, path = obj.frame(name), obj.path(name)
        if frame is not None:
            head, dotted, local = f"**{owner}.{name}**: frame of `{owner}`", f"{owner}.{name}", frame.pose
        elif path is not None:
            return f"**{owner}.{name}**: path of `{owner}` with {len(path.points)} points ({world.path})"
        elif name in obj.soft or name in obj.spatial:
            return f"**{owner}.{name}**: attribute of `{owner}` = `{({**obj.spatial, **obj.soft})[name]}`"
        else:
            return None
    parts = [head, f"= {shown_pose(local).text()} relative to `{local.frame}`"]
    if obj.tool:
        return "\n\n".join(parts + [f"({world.path})"])
    try:
        parts.append(f"= {shown_pose(world.world_pose(dotted)).text()} in world")
    except WorldError:  # a pose below the flange is known only at run time
        pass
    return "\n\n".join(parts + [f"({world.path})"])


def _attribute_hover(program: n.Program, clause: n.With, registry: Registry) -> str | None:
    for node in program.walk():
        if isinstance(node, n.Motion) and any(c is clause for c in node.clauses):
            spec = registry.motions.get(node.keyword)
            attribute = spec.attribute(clause.name.id) if spec is not None else None
        elif isinstance(node, n.Install) and any(c is clause for c in node.attributes):
            kind = registry.install_kinds.get(node.kind.id)
            attribute = kind.attribute(clause.name.id) if kind is not None else None
        else:
            continue
        if attribute is None:
            return None
        return f"**{attribute.name}**: {attribute_detail(attribute)}\n\n{attribute.doc}"
    return None


def _method_hover(registry: Registry, install: n.Install, name: str) -> str | None:
    """`Gun.Close`, `Laser.Distance`: a method or sensor value of the installed kind."""
    kind = registry.install_kinds.get(install.kind.id)
    method = kind.method(name) if kind is not None else None
    if method is None:
        return None
    what = "command" if method.returns is None else f"value: {type_with_unit(method.returns)}"
    return f"**{install.name.id}.{name}** ({kind.name} {what}): {method.doc}"  # type: ignore[union-attr]


def hover_text(analysis: Analysis, index: ProgramIndex | None, registry: Registry, line0: int, character: int) -> str | None:
    """Markdown for the 0-based position, or None when there is nothing to say."""
    lines = analysis.text.splitlines()
    word = word_at(lines[line0], character) if line0 < len(lines) else None
    if word is not None and (word.endswith("MOVE") or word.endswith("move") or word == "moveto"):
        found = motion_hover(registry, word)
        if found is not None:
            return found
    if analysis.program is None or index is None:
        return None
    target: Target | None = name_at(analysis.program, line0 + 1, character + 1)
    if target is None:
        return None
    name = target.name.id
    if isinstance(target.parent, n.With) and target.parent.name is target.name:
        return _attribute_hover(analysis.program, target.parent, registry)
    if isinstance(target.parent, n.Install) and target.parent.kind is target.name:
        kind = registry.install_kinds.get(name)
        return f"**{name}**: INSTALL kind. {kind.doc}" if kind is not None else None
    owner = target.owner
    definition = index.lookup(name, line0 + 1) if owner is None else None
    if definition is not None:
        return definition_hover(definition, lines, index)
    installed = index.lookup(owner.id, line0 + 1) if owner is not None else None
    if installed is not None and isinstance(installed.statement, n.Install):
        return _method_hover(registry, installed.statement, name)
    if analysis.world is not None:
        found = world_hover(analysis.world, owner.id if owner is not None else None, name)
        if found is not None:
            return found
    if owner is None and name in registry.functions:
        spec = registry.functions[name]
        params = ", ".join(p.name for p in spec.params)
        return f"**{name}**({params}): {spec.doc}"
    return None

