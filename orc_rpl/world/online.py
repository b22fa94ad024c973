"""The on-line world (thesis 7.1-7.2): spatial and soft attributes stay, model attributes become keys into an off-line store."""

from __future__ import annotations

from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Mapping

from orc_rpl.world.editing import Patch, apply
from orc_rpl.world.objects import WorldError
from orc_rpl.world.source import find
from orc_rpl.world.world import World


@dataclass(frozen=True)
class ModelStore:
    """The off-line model database: the exact text of each object's `model:` entry, by key (the object's name)."""

    source: str                                                  #: the off-line world file they came from
    entries: Mapping[str, str] = field(default_factory=lambda: MappingProxyType({}))


def split_model_attributes(world: World) -> tuple[World, ModelStore]:
    """The on-line world (each `model:` entry replaced by `model_key: <name>`) and the store that gives them back."""
    src = world.parsed.src
    patches, entries = [], {}
    for obj in world.objects:
        if obj.model is None:
            continue
        _, mapping = world.parsed.object_nodes[obj.name]
        key_node, value = find(mapping, "model")
        first, last = key_node.start_mark.line, src.last_line(value)
        start, end = src.index(first, 0), src.line_end(last)
        entries[obj.name] = src.text[start:end]
        indent = " " * key_node.start_mark.column
        # Keep the entry's own line ending, so a model at the end of a file without a final newline restores exactly.
        ending = src.text[start:end][len(src.text[start:end].rstrip("\r\n")):]
        patches.append(Patch(start, end, f"{indent}model_key: {obj.name}{ending}"))
    online = world._reloaded(apply(src.text, patches))
    return online, ModelStore(world.path, MappingProxyType(entries))


def restore_model_attributes(online: World, store: ModelStore) -> World:
    """The off-line world back: every `model_key:` line replaced by the stored `model:` entry, byte for byte."""
    src = online.parsed.src
    patches = []
    for obj in online.objects:
        if obj.model_key is None:
            continue
        if obj.model_key not in store.entries:
            raise WorldError(f"model key '{obj.model_key}' of '{obj.name}' is not in the model store of {store.source}")
        _, mapping = online.parsed.object_nodes[obj.name]
        key_node, value = find(mapping, "model_key")
        start, end = src.index(key_node.start_mark.line, 0), src.line_end(src.last_line(value))
        stored = store.entries[obj.model_key]
        # An entry taken from the middle of a file ends with a line break; one added on-line after it may need one.
        if end == len(src.text) and not src.text.endswith(("\n", "\r")):
            stored = stored.rstrip("\r\n")
        patches.append(Patch(start, end, stored))
    return online._reloaded(apply(src.text, patches))
