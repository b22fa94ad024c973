"""libyaml (fast) and ruamel (reference) compose every world file to the same tags, values and positions."""

from __future__ import annotations

from pathlib import Path

import pytest
from ruamel.yaml import YAML

from orc_rpl.world import source
from orc_rpl.world.source import MappingNode, SequenceNode, SourceText

ROOT = Path(__file__).resolve().parent.parent.parent
WORLDS = sorted([*ROOT.glob("worlds/*.yaml"), *ROOT.glob("tests/transform/worlds/*.yaml")])

pytestmark = pytest.mark.skipif(source._libyaml is None, reason="PyYAML without libyaml: only ruamel composes")


def _flat(node):  # type: ignore[no-untyped-def]
    """Every node as (kind, tag, scalar value, start, end, style), depth first."""
    out = []
    stack = [node]
    while stack:
        item = stack.pop()
        kind = "map" if isinstance(item, MappingNode) else "seq" if isinstance(item, SequenceNode) else "scalar"
        out.append((kind, item.tag, item.value if kind == "scalar" else None, (item.start_mark.line, item.start_mark.column),
                    (item.end_mark.line, item.end_mark.column), (item.style or None) if kind == "scalar" else bool(item.flow_style)))
        if kind == "map":
            stack.extend(x for pair in reversed(item.value) for x in reversed(pair))
        elif kind == "seq":
            stack.extend(reversed(item.value))
    return out


EXTRA = "world:\n  a:\n    soft: {flag: yes, octal: 010, none: ~, t: 2s, text: 'q', n: -1.5e3, b: TRUE}\n"


@pytest.mark.parametrize("text", [*(p.read_text() for p in WORLDS), EXTRA], ids=[*(p.stem for p in WORLDS), "yaml_1_2_tags"])
def test_both_parsers_agree(text: str) -> None:
    fast = SourceText(text, "w.yaml").compose()
    assert type(fast).__module__.startswith("yaml"), "the fast path must be taken"
    assert _flat(fast) == _flat(YAML(typ="rt").compose(text))
