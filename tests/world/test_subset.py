"""The reader of the YAML subset world files use gives libyaml's nodes exactly (tags, styles, marks), or leaves the text to libyaml."""

from __future__ import annotations

import random
import sys
from pathlib import Path

import pytest

from orc_rpl.world import loads_world
from orc_rpl.world import source as yaml_source
from orc_rpl.world.subset import compose_subset
from tests import fuzz_inputs

ROOT = Path(__file__).resolve().parent.parent.parent
WORLDS = sorted([*ROOT.glob("worlds/*.yaml"), *ROOT.glob("tests/**/worlds/*.yaml")])


def _libyaml(text: str) -> object:
    loader = yaml_source._Yaml12Loader(text)
    try:
        return loader.get_single_node()
    except yaml_source._libyaml.YAMLError:
        return "error"
    finally:
        loader.dispose()


def _shape(node: object) -> object:
    """Everything a reader of the nodes can see: class, tag, value, style, flow style, where it starts and ends."""
    if node is None or isinstance(node, str):
        return node
    marks = tuple((m.line, m.column, m.index) for m in (node.start_mark, node.end_mark))  # type: ignore[attr-defined]
    head = (type(node).__name__, node.tag, getattr(node, "style", None), getattr(node, "flow_style", None), marks)  # type: ignore[attr-defined]
    if isinstance(node.value, list):  # type: ignore[attr-defined]
        return head + tuple(tuple(map(_shape, item)) if isinstance(item, tuple) else _shape(item) for item in node.value)  # type: ignore[attr-defined]
    return head + (node.value,)  # type: ignore[attr-defined]


def _same_or_left_to_libyaml(text: str) -> bool:
    """True when the subset reader read the text (and then exactly as libyaml does)."""
    ours = compose_subset(text, yaml_source.plain_tag)
    if ours is None:
        return False
    assert _shape(ours) == _shape(_libyaml(text)), text
    return True


@pytest.mark.parametrize("world", WORLDS, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_world_is_read_by_the_subset_reader_as_libyaml_reads_it(world: Path) -> None:
    text = world.read_text()
    assert _same_or_left_to_libyaml(text)
    assert loads_world(text, str(world)).dump() == text


def test_the_benchmarks_generated_world() -> None:
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from bench_transform import make_world

    text, _ = make_world(600, random.Random(7))
    assert _same_or_left_to_libyaml(text)
    assert loads_world(text).dump() == text


ODD = [
    "robot:\n  model: irb2400\nworld:\n",
    "robot:\n  model: irb2400\nworld:",
    "robot:\n    model: x\n    pose:   [ 1 ,2,  3 ]  # c\nworld:\n     a:\n         pose: [1mm,2]\n\n\n# end\n",
    "robot:\n  model: x\nworld:\n  a:\n    frames:\n      p: [0, 0, 0, 0, 0, 0, {turn: 0, track: 2mm}]\n    paths:\n      e:\n"
    "      - [1, 2]\n      - [3, 4]\n      f:\n        - [1]\n  b:\n",
    "robot:\n  model: x\nworld:\n  a: yes\n  b: 0x1F\n  c: .nan\n  d: ~\n  e: null\n  f: 1e3\n  g: 010\n  h: -0\n  i: true\n",
    "robot:\n  model: x\nworld:\n  a: x#y\n  b: x #y\n  c: [a#b, c]\n  d: {}\n  e: []\n  f: {a: [1, {b: 2}]}\n",
    "robot:\n  model: x\nworld:\n  a: a b c\n  b: [a b, c d]\n  c: x:y\n  d: [x:y]\n  e: -1\n",
    "robot:\n  model: x\nworld:\n  a:\n\n  # c\n\n    b: 1\n  c:\n    d:\n      e:\n  f: 1\n",
    "\n\n# only a comment first\nrobot:\n  model: x\nworld:\n  station:\n    pose: [1, 0, 0, 0, 0, 0]\n ",
    "robot:\n  model: x\nworld:\n  a:\n    pose: [1, 2]   # trailing\n    # a comment deeper\n# a comment at the left\n  b: 2",
    # outside the subset, or not YAML at all: libyaml decides
    "robot:\n  model: x\nworld:\n  a:\n    x: 1\n   y: 2\n",
    "robot:\n  model: x\nworld:\n  a: 1\n    b: 2\n",
    "robot:\n  model: x\nworld:\n  a:\n    - 1\n    b: 2\n",
    "robot:\n  model: x\nworld:\n  a: [1, 2\n  b: 2\n",
    "robot:\n  model: x\nworld:\n  a: [1, 2,]\n  b: b: c\n",
    "robot:\n  model: x\nworld:\n  a: 'quoted'\n  b: \"q\"\n  c: |\n    text\n",
    "robot:\n  model: x\nworld:\n  a: &anchor [1]\n  b: *anchor\n",
    "robot:\n  model: x\nworld:\n  a: [x] y\n  b: [x]# y\n",
    "robot:\n\tmodel: x\n",
    "robot:\r\n  model: x\r\n",
    "robot:\n  model: caf\u00e9\n",
    "  robot:\n    model: x\n",
    "---\nrobot:\n  model: x\n",
]


@pytest.mark.parametrize("text", ODD)
def test_odd_layouts_are_read_as_libyaml_reads_them_or_left_to_it(text: str) -> None:
    _same_or_left_to_libyaml(text)


def _layout(rng: random.Random) -> str:
    """A world in a random but legal layout: indentation widths, blanks, comments, flow spacing, sequence styles."""
    step = rng.choice((1, 2, 3, 4))
    blank = lambda: rng.choice(("", "", "\n", "\n\n", "  \n"))  # noqa: E731
    comment = lambda: rng.choice(("", "", "  # note", "    # aligned note", " #x"))  # noqa: E731
    colon = lambda: rng.choice((": ", ":  ", ":   "))  # noqa: E731

    def flow(values: list[str]) -> str:
        space, comma = rng.choice(("", " ", "  ")), rng.choice((", ", ",", " , ", ",  "))
        return "[" + space + comma.join(values) + space + "]"

    def pose() -> str:
        return flow([rng.choice(("0", "1", "-2.5", "100mm", "-30mm", "90deg", "1e-3", ".5")) for _ in range(6)])

    lines = [rng.choice(("", "# a world\n")) + "robot:" + comment(), " " * step + "model" + colon() + "irb2400" + comment(),
             " " * step + "pose" + colon() + pose(), blank() + "world:" + comment()]
    for number in range(rng.randint(1, 6)):
        at = " " * step
        lines += [blank() + at + f"object{number}:" + comment(), at * 2 + "pose" + colon() + pose() + comment()]
        if rng.random() < 0.5:
            lines.append(at * 2 + "model" + colon() + "{geometry" + colon() + "box, size" + colon()
                         + flow(["100mm", "50mm", "20mm"]) + "}")
        if rng.random() < 0.5:
            lines += [at * 2 + "frames:" + comment(), rng.choice(("", at * 3 + "# taught\n")) + at * 3 + "p" + colon() + pose()]
        if rng.random() < 0.5:
            entry = at * rng.choice((3, 4))  # an indentless sequence (level with its key) or an indented one
            lines += [at * 2 + "paths:", at * 3 + "edge:"] + [entry + "-" + rng.choice((" ", "  ")) + pose() for _ in range(2)]
        if rng.random() < 0.3:
            lines.append(at * 2 + "soft:" + rng.choice(("", "  # none yet")))
    text = "\n".join(lines)
    return text + rng.choice(("\n", "", "\n\n", "\n# end\n", "\n  "))


def test_generated_layouts_are_read_exactly_as_libyaml_reads_them() -> None:
    rng = random.Random(5)
    read = sum(_same_or_left_to_libyaml(_layout(rng)) for _ in range(400))
    assert read >= 350  # the subset covers these layouts: nearly all are read by it


def test_hostile_worlds_are_read_as_libyaml_reads_them_or_left_to_it() -> None:
    rng = random.Random(6)
    for _ in range(400):
        _same_or_left_to_libyaml(fuzz_inputs.world(rng))
