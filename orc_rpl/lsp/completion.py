"""Completion: what may be written at the cursor, read from the line being typed (the program need not parse)."""

from __future__ import annotations

import re

from lsprotocol import types as T

from orc_rpl.application.registry import Registry
from orc_rpl.lsp.index import ProgramIndex
from orc_rpl.lsp.words import OFFLINE_MOTION, ONLINE_MOTION, attribute_detail, keywords, registry_keyword
from orc_rpl.syntax.lexicon import PREDEFINED_NAMES
from orc_rpl.world import World

_WORD_BEFORE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*$")
_INSTALL_KIND = re.compile(r"^\s*(?:INSTALL|install)\s+\w+\s+(?:AS|as)\s+\w*$")
_INSTALL_LINE = re.compile(r"^\s*(?:INSTALL|install)\s+\w+\s+(?:AS|as)\s+(\w+)\b")
_FIELD_BEFORE = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)\.[A-Za-z0-9_]*$")
_CONTINUATION = re.compile(r"^\s*(WITH|VIA|UNTIL|with|via|until)\b")

_KINDS = {
    "tool": T.CompletionItemKind.Variable, "frame": T.CompletionItemKind.Module, "position": T.CompletionItemKind.Constant,
    "path": T.CompletionItemKind.Constant, "constant": T.CompletionItemKind.Constant, "variable": T.CompletionItemKind.Variable,
    "enum": T.CompletionItemKind.Enum, "enum value": T.CompletionItemKind.EnumMember, "installed": T.CompletionItemKind.Class,
    "proc": T.CompletionItemKind.Function, "func": T.CompletionItemKind.Function, "parameter": T.CompletionItemKind.Variable,
    "local": T.CompletionItemKind.Variable,
}


def statement_head(lines: list[str], line0: int) -> tuple[int, str]:
    """The line (0-based) and text where the statement holding `line0` starts: continuation lines go up to their motion."""
    while line0 > 0 and _CONTINUATION.match(lines[line0]):
        line0 -= 1
    return line0, lines[line0] if line0 < len(lines) else ""


def _item(label: str, kind: T.CompletionItemKind, detail: str = "", insert: str | None = None,
          doc: str = "") -> T.CompletionItem:
    return T.CompletionItem(label=label, kind=kind, detail=detail or None, insert_text=insert,
                            documentation=T.MarkupContent(T.MarkupKind.Markdown, doc) if doc else None)


def attribute_items(registry: Registry, keyword: str, offline: bool) -> list[T.CompletionItem]:
    """The attributes the motion keyword declares, each with its type, unit and default."""
    spec = registry.motions.get(registry_keyword(keyword))
    if spec is None:
        return []
    out = []
    for attribute in spec.attributes:
        name = attribute.name.lower() if offline else attribute.name
        out.append(_item(name, T.CompletionItemKind.Property, attribute_detail(attribute),
                         f"{name}=" if offline else f"{name} = ", attribute.doc))
    return out


def _install_attribute_items(registry: Registry, kind_name: str, offline: bool) -> list[T.CompletionItem]:
    kind = registry.install_kinds.get(kind_name)
    if kind is None:
        return []
    return [_item(a.name.lower() if offline else a.name, T.CompletionItemKind.Property, attribute_detail(a),
                  f"{a.name.lower()}=" if offline else f"{a.name} = ", a.doc) for a in kind.attributes]


def _name_items(index: ProgramIndex | None, line: int, registry: Registry, world: World | None) -> list[T.CompletionItem]:
    out: list[T.CompletionItem] = []
    if index is not None:
        for definition in index.visible(line).values():
            out.append(_item(definition.name, _KINDS.get(definition.kind, T.CompletionItemKind.Variable), definition.kind))
    out += [_item(name, T.CompletionItemKind.Function, "function", doc=spec.doc) for name, spec in registry.functions.items()]
    out += [_item(name, T.CompletionItemKind.Constant, "predefined") for name in sorted(PREDEFINED_NAMES)]
    if world is not None:
        for obj in world.objects:
            detail = "world tool" if obj.tool else "world object" + (" (on-line frame)" if obj.online_frame else "")
            out.append(_item(obj.name, T.CompletionItemKind.Module, detail))
    return out


def _field_items(owner: str, index: ProgramIndex | None, line: int, registry: Registry,
                 world: World | None) -> list[T.CompletionItem]:
    """After `owner.`: a world object's frames, paths and attributes, or an installed object's methods."""
    if world is not None and owner in {o.name for o in world.objects}:
        obj = world.object(owner)
        return ([_item(f.name, T.CompletionItemKind.Constant, f"frame of {owner}") for f in obj.frames]
                + [_item(p.name, T.CompletionItemKind.Constant, f"path of {owner} ({len(p.points)} points)") for p in obj.paths]
                + [_item(k, T.CompletionItemKind.Field, f"attribute of {owner}") for k in (*obj.spatial, *obj.soft)])
    definition = index.lookup(owner, line) if index is not None else None
    if definition is not None and definition.kind == "installed":
        kind = registry.install_kinds.get(definition.statement.kind.id)  # type: ignore[attr-defined]
        if kind is not None:
            return [_item(m.name, T.CompletionItemKind.Method, m.doc) for m in kind.methods]
    if owner == "ROBOT":
        return [_item(word, T.CompletionItemKind.Field, "software sensor") for word in ("Joints", "Torque", "PosError", "Thermal")]
    return []


def complete(lines: list[str], line0: int, character: int, registry: Registry, index: ProgramIndex | None,
             world: World | None, offline: bool, after_space: bool = False) -> list[T.CompletionItem]:
    """Completion items for the 0-based cursor position; `after_space` (the editor asked because a space was typed)
    answers only where a space leads to a short list: after WITH, after INSTALL ... AS, after an off-line motion's target."""
    text = lines[line0] if line0 < len(lines) else ""
    before = text[:character]
    partial = _WORD_BEFORE.search(before)
    start = before[: partial.start()] if partial else before
    field = _FIELD_BEFORE.search(before)
    if field is not None:
        return _field_items(field.group(1), index, line0 + 1, registry, world)
    if _INSTALL_KIND.match(before):
        return [_item(k.name, T.CompletionItemKind.Class, "INSTALL kind", doc=k.doc) for k in registry.install_kinds.values()]
    head_line, head = statement_head(lines, line0)
    head_text = head if head_line != line0 else before
    motion = (OFFLINE_MOTION if offline else ONLINE_MOTION).match(head_text)
    after_with = re.search(r"\b(WITH|with)\s+$", start) is not None
    if motion is not None and (after_with or (offline and head_line == line0 and start.rstrip() != start
                                                 and len(start.split()) >= 3)):
        attributes = attribute_items(registry, motion.group(1), offline)
        return attributes if after_with else attributes + _name_items(index, line0 + 1, registry, world)
    install = _INSTALL_LINE.match(head_text)
    if install is not None and (after_with or offline):
        return _install_attribute_items(registry, install.group(1), offline)
    if after_space:
        return []
    items = _name_items(index, line0 + 1, registry, world)
    if not start.strip():  # the first word of a statement: keywords and motion keywords too
        motions = [m.lower() for m in registry.motions] + ["moveto"] if offline else list(registry.motions)
        items += [_item(word, T.CompletionItemKind.Keyword, "motion keyword") for word in motions]
        items += [_item(word, T.CompletionItemKind.Keyword, "keyword") for word in keywords(offline)]
    return items
