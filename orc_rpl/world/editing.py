"""Edits of a world file as small text patches at node positions, so every other byte (comments, spacing) stays."""

from __future__ import annotations

from dataclasses import dataclass

from orc_rpl.world.loader import Parsed
from orc_rpl.world.objects import WorldError
from orc_rpl.world.source import MappingNode, Node, ScalarNode, SourceText, find

DEFAULT_STEP = 2


@dataclass(frozen=True, slots=True)
class Patch:
    """Replace text[start:end] by `text` (start == end inserts)."""

    start: int
    end: int
    text: str


def apply(text: str, patches: list[Patch]) -> str:
    """The text with non-overlapping patches applied (later offsets first, so earlier ones stay valid)."""
    for p in sorted(patches, key=lambda p: (p.start, p.end), reverse=True):
        text = text[: p.start] + p.text + text[p.end :]
    return text


def _value_span(src: SourceText, node: Node) -> tuple[int, int]:
    """Where a value's text is: a block collection ends at its last content line, not at the next token."""
    start = src.index(node.start_mark.line, node.start_mark.column)
    if isinstance(node, ScalarNode) or node.flow_style:
        return start, src.index(node.end_mark.line, node.end_mark.column)
    last = src.last_line(node)
    return start, src.index(last, 0) + len(src.line(last).rstrip())


def _insert_after(src: SourceText, node: Node, lines: list[str]) -> Patch:
    """Insert whole lines after the last line holding text of `node`."""
    at = src.line_end(src.last_line(node))
    nl = src.newline
    lead = nl if at == len(src.text) and src.text and not src.text.endswith("\n") else ""
    return Patch(at, at, lead + "".join(line + nl for line in lines))


def _key_column(mapping: MappingNode) -> int:
    return mapping.value[0][0].start_mark.column


def _object(parsed: Parsed, name: str) -> tuple[ScalarNode, MappingNode]:
    try:
        return parsed.object_nodes[name]
    except KeyError:
        raise WorldError(f"no object '{name}' in {parsed.src.path}") from None


def set_attribute(parsed: Parsed, name: str, key: str, value_text: str) -> Patch:
    """Set an object's single-line attribute (parent, pose, online_frame, tool, model_key) to `value_text`."""
    src = parsed.src
    key_node, mapping = _object(parsed, name)
    entry = find(mapping, key)
    if entry is not None:
        start, end = _value_span(src, entry[1])
        return Patch(start, end, value_text)
    indent = " " * _key_column(mapping)
    line = f"{indent}{key}: {value_text}"
    if key == "parent":
        # The parent reads first: it says what the pose below is relative to.
        first = mapping.value[0][0].start_mark.line
        at = src.index(first, 0)
        return Patch(at, at, line + src.newline)
    return _insert_after(src, mapping, [line])


def set_entry(parsed: Parsed, name: str, section: str, entry_name: str, value_text: str) -> Patch:
    """Set or add `entry_name: value_text` in an object's `frames:` or `soft:` section (added if missing)."""
    src = parsed.src
    key_node, mapping = _object(parsed, name)
    indent = _key_column(mapping)
    step = indent - key_node.start_mark.column or DEFAULT_STEP
    found = find(mapping, section)
    if found is None:
        return _insert_after(src, mapping, [f"{' ' * indent}{section}:", f"{' ' * (indent + step)}{entry_name}: {value_text}"])
    sec_key, sec = found
    if isinstance(sec, ScalarNode) and sec.tag.endswith(":null"):
        return _insert_after(src, sec_key, [f"{' ' * (indent + step)}{entry_name}: {value_text}"])
    if not isinstance(sec, MappingNode) or sec.flow_style:
        raise WorldError(f"{src.path}:{sec.start_mark.line + 1}: '{section}' of '{name}' is not a block mapping; edit it by hand")
    existing = find(sec, entry_name)
    if existing is not None:
        start, end = _value_span(src, existing[1])
        return Patch(start, end, value_text)
    return _insert_after(src, sec, [f"{' ' * _key_column(sec)}{entry_name}: {value_text}"])


def add_object(parsed: Parsed, name: str, attributes: list[tuple[str, str]]) -> Patch:
    """Append an object with single-line attributes at the end of the `world:` mapping (made if missing)."""
    src = parsed.src
    if name in parsed.object_nodes:
        raise WorldError(f"object '{name}' already exists in {src.path}")
    root = parsed.root
    found = find(root, "world") if root is not None else None
    if found is None or (isinstance(found[1], ScalarNode) and found[1].tag.endswith(":null")):
        col, step = 2, DEFAULT_STEP
    else:
        objects = found[1]
        col = _key_column(objects)
        first_attrs = objects.value[0][1]
        step = (_key_column(first_attrs) - col if isinstance(first_attrs, MappingNode) and first_attrs.value else 0) or DEFAULT_STEP
    lines = [f"{' ' * col}{name}:"] + [f"{' ' * (col + step)}{k}: {v}" for k, v in attributes]
    if found is None:
        nl, at = src.newline, len(src.text)
        lead = nl if src.text and not src.text.endswith("\n") else ""
        return Patch(at, at, lead + "world:" + nl + "".join(line + nl for line in lines))
    if isinstance(found[1], ScalarNode):
        return _insert_after(src, found[0], lines)
    return _insert_after(src, found[1], lines)


def replace_lines(src: SourceText, first_line0: int, last_line0: int, text: str) -> Patch:
    """Replace whole lines first..last (0-based, with their line breaks) by `text`."""
    return Patch(src.index(first_line0, 0), src.line_end(last_line0), text)
