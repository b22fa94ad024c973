"""Exact round trips: every off-line program with its world, every on-line program, and the thesis' own listing."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from orc_rpl.syntax.files import declared_world
from orc_rpl.syntax.offline_parser import parse_offline
from orc_rpl.syntax.offline_printer import print_offline
from orc_rpl.syntax.parser import parse
from orc_rpl.syntax.printer import print_program
from orc_rpl.transform.pipeline import to_offline, to_online
from orc_rpl.world import load_world, loads_world
from tests.transform.helpers import HERE, ROOT

OFFLINE = sorted((ROOT / "programs" / "offline").glob("*.orl"))
ONLINE = sorted((ROOT / "programs" / "online").glob("*.rpl"))
FOREIGN = sorted((ROOT / "tests" / "checking" / "foreign").glob("*.rpl")) + sorted((HERE / "foreign").glob("*.rpl"))
GOLDEN = HERE / "golden"
#: Set to regenerate the golden on-line forms (read the diff before committing).
REGENERATE = os.environ.get("ORC_REGENERATE_GOLDEN") == "1"


def world_of(program: Path) -> Path:
    found = declared_world(program, program.read_text(encoding="utf-8"))
    assert found is not None, f"{program.name} has no '# world:' line"
    return found


@pytest.mark.parametrize("program", OFFLINE, ids=lambda p: p.stem)
def test_offline_program_and_world_come_back_byte_for_byte(program: Path) -> None:
    text, world_path = program.read_text(encoding="utf-8"), world_of(program)
    world = load_world(world_path)
    job = to_online(parse_offline(text, str(program)), world, str(program), text)
    online_text = print_program(job.program)
    back = to_offline(parse(online_text, "online.rpl"), load_world(world_path))
    assert print_offline(back.program) == text
    assert back.world.dump() == world_path.read_text(encoding="utf-8")


@pytest.mark.parametrize("program", OFFLINE, ids=lambda p: p.stem)
def test_offline_program_transforms_to_its_golden_online_form(program: Path) -> None:
    text = program.read_text(encoding="utf-8")
    online_text = print_program(to_online(parse_offline(text, str(program)), load_world(world_of(program))).program)
    golden = GOLDEN / f"{program.stem}.rpl"
    if REGENERATE:
        golden.write_text(online_text, encoding="utf-8")
    assert online_text == golden.read_text(encoding="utf-8")


def _online_round_trip(text: str) -> None:
    job = to_offline(parse(text, "program.rpl"), None)
    offline_text, world_text = print_offline(job.program), job.world.dump()
    world = loads_world(world_text, "made.yaml")
    assert print_program(to_online(parse_offline(offline_text, "program.orl"), world).program) == text


@pytest.mark.parametrize("program", ONLINE, ids=lambda p: p.stem)
def test_online_program_comes_back_byte_for_byte(program: Path) -> None:
    _online_round_trip(program.read_text(encoding="utf-8"))


@pytest.mark.parametrize("program", FOREIGN, ids=lambda p: p.stem)
def test_programs_written_by_others_come_back_in_canonical_form(program: Path) -> None:
    _online_round_trip(print_program(parse(program.read_text(encoding="utf-8"))))


def test_thesis_7_3_gives_the_thesis_listing_exactly() -> None:
    text = (ROOT / "programs" / "offline" / "thesis_7_3.orl").read_text(encoding="utf-8")
    online_text = print_program(to_online(parse_offline(text), load_world(ROOT / "worlds" / "cell_thesis.yaml")).program)
    statements = [line for line in online_text.splitlines() if not line.startswith(("POS ", "FRAME base_plate =", "--"))]
    assert statements == [
        "MOVE ARM TO pos0",
        "FRAME base_plate",
        "    MOVE ARM TO pos1",
        "    MOVE ARM TO pos2",
        "ENDFRAME",
        "MOVE ARM TO pos3",
    ]


def test_an_online_program_made_online_puts_its_positions_into_a_new_world() -> None:
    text = (ROOT / "programs" / "online" / "thesis_7_3_online_frame.rpl").read_text(encoding="utf-8")
    job = to_offline(parse(text), None)
    assert "moveto base_plate.pos1\n" in print_offline(job.program)
    world = job.world
    assert world.object("base_plate").online_frame
    assert [f.name for f in world.object("base_plate").frames] == ["pos1", "pos2"]
    assert world.object("pos0").parent == "world"


@pytest.mark.parametrize("program", sorted((HERE / "foreign").glob("*.orl")), ids=lambda p: p.stem)
def test_offline_programs_written_by_others_come_back_in_canonical_form(program: Path) -> None:
    text = print_offline(parse_offline(program.read_text(encoding="utf-8"), str(program)))
    world_path = world_of(program)
    online_text = print_program(to_online(parse_offline(text), load_world(world_path)).program)
    back = to_offline(parse(online_text), load_world(world_path))
    assert print_offline(back.program) == text
    assert back.world.dump() == world_path.read_text(encoding="utf-8")
