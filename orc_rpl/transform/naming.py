"""On-line names of world entities: short where the world has one such name, qualified (`fixture_a_pos1`) where it clashes; a bijection."""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType
from typing import Mapping

from orc_rpl.syntax.lexicon import PREDEFINED_NAMES, is_reserved
from orc_rpl.world import World

#: What an entity is, which decides the on-line declaration it becomes.
OBJECT, FRAME, PATH = "object", "frame", "path"


@dataclass(frozen=True)
class Names:
    """The on-line name of every object, frame and path of a world (`base_plate.pos1` -> `pos1`), and back."""

    online: Mapping[str, str]          #: dotted entity -> on-line name
    entity: Mapping[str, str]          #: on-line name -> dotted entity
    kinds: Mapping[str, str]           #: dotted entity -> OBJECT, FRAME or PATH

    def name_of(self, dotted: str) -> str:
        return self.online[dotted]


def world_entities(world: World) -> list[tuple[str, str, str]]:
    """(dotted, short name, kind) of every object, frame and path, objects first, each in file order."""
    out = [(o.name, o.name, OBJECT) for o in world.objects]
    for o in world.objects:
        out += [(f"{o.name}.{f.name}", f.name, FRAME) for f in o.frames]
        out += [(f"{o.name}.{p.name}", p.name, PATH) for p in o.paths]
    return out


def name_world(world: World) -> Names:
    """The on-line names: an object keeps its name; a frame or path takes its own name when no other entity has it.

    A clash (`fixture_a.pos1`, `fixture_b.pos1`) gives both `owner_name`; if that is taken too, `_2`, `_3`, ...
    follow in file order. The names depend on the world alone, so the inverse finds the entity of a name.
    """
    entities = world_entities(world)
    counts: dict[str, int] = {}
    for _, short, _ in entities:
        counts[short] = counts.get(short, 0) + 1
    taken = {short for dotted, short, kind in entities if kind == OBJECT}
    taken |= {short for dotted, short, kind in entities if kind != OBJECT and counts[short] == 1}
    online: dict[str, str] = {}
    kinds: dict[str, str] = {}
    for dotted, short, kind in entities:
        kinds[dotted] = kind
        if kind == OBJECT or (counts[short] == 1 and not _unusable(short)):
            online[dotted] = short
            continue
        candidate = dotted.replace(".", "_")
        number = 1
        while candidate in taken or _unusable(candidate):
            number += 1
            candidate = f"{dotted.replace('.', '_')}_{number}"
        taken.add(candidate)
        online[dotted] = candidate
    entity = {name: dotted for dotted, name in online.items()}
    return Names(MappingProxyType(online), MappingProxyType(entity), MappingProxyType(kinds))


def _unusable(name: str) -> bool:
    """Names an on-line program cannot declare."""
    return is_reserved(name) or name in PREDEFINED_NAMES
