"""Edits made on-line come back to the right place of the off-line program and world model."""

from __future__ import annotations

from orc_rpl.syntax.offline_parser import parse_offline
from orc_rpl.syntax.offline_printer import print_offline
from orc_rpl.syntax.parser import parse
from orc_rpl.syntax.printer import print_program
from orc_rpl.transform.pipeline import to_offline, to_online
from orc_rpl.world import load_world
from tests.transform.helpers import ROOT

CELL = ROOT / "worlds" / "cell_thesis.yaml"
PROGRAM = "moveto pos0\nmoveto base_plate.pos1\nmoveto base_plate.pos2\nmoveto pos3\n"


def online_text() -> str:
    return print_program(to_online(parse_offline(PROGRAM), load_world(CELL)).program)


def back(edited: str):  # type: ignore[no-untyped-def]
    return to_offline(parse(edited, "edited.rpl"), load_world(CELL))


def changed_lines(before: str, after: str) -> list[tuple[str, str]]:
    return [(a, b) for a, b in zip(before.splitlines(), after.splitlines()) if a != b]


def test_position_taught_inside_a_frame_block_goes_into_that_frame() -> None:
    edited = online_text().replace(
        "POS pos3", "POS pos1b = POSE(0, 0, 60mm, -90deg, 180deg, 0) IN base_plate\nPOS pos3").replace(
        "    MOVE ARM TO pos1\n", "    MOVE ARM TO pos1\n    MOVE ARM TO pos1b\n")
    job = back(edited)
    assert print_offline(job.program) == ("moveto pos0\nmoveto base_plate.pos1\nmoveto base_plate.pos1b\n"
                                          "moveto base_plate.pos2\nmoveto pos3\n")
    world = job.world.dump()
    assert "      pos2: [-50mm, 40mm, 60mm, -90deg, 180deg, 0]\n      pos1b: [0, 0, 60mm, -90deg, 180deg, 0]\n" in world
    # The next conversion declares it in its frame and moves to it inside the block.
    again = print_program(to_online(job.program, job.world).program)
    assert "POS pos1b = POSE(0, 0, 60mm, -90deg, 180deg, 0) IN base_plate\n" in again
    assert "FRAME base_plate\n    MOVE ARM TO pos1\n    MOVE ARM TO pos1b\n    MOVE ARM TO pos2\nENDFRAME\n" in again


def test_touched_up_position_changes_one_line_of_the_world() -> None:
    edited = online_text().replace("POS pos2 = POSE(-50mm, 40mm, 60mm", "POS pos2 = POSE(-52mm, 41mm, 60mm")
    job = back(edited)
    assert print_offline(job.program) == PROGRAM
    assert changed_lines(CELL.read_text(), job.world.dump()) == [
        ("      pos2: [-50mm, 40mm, 60mm, -90deg, 180deg, 0]", "      pos2: [-52mm, 41mm, 60mm, -90deg, 180deg, 0]")]


def test_position_in_the_world_touched_up_moves_its_object() -> None:
    edited = online_text().replace("POS pos0 = POSE(800mm, -300mm, 900mm", "POS pos0 = POSE(810mm, -300mm, 900mm")
    assert changed_lines(CELL.read_text(), back(edited).world.dump()) == [
        ("    pose: [800mm, -300mm, 900mm, 0, 180deg, 0]", "    pose: [810mm, -300mm, 900mm, 0, 180deg, 0]")]


def test_inserted_move_appears_at_its_place_off_line() -> None:
    edited = online_text().replace("MOVE ARM TO pos3\n", "MOVE ARM TO pos3\nWAIT 1s\nMOVE ARM TO pos0\n")
    job = back(edited)
    assert print_offline(job.program) == PROGRAM + "wait 1s\nmoveto pos0\n"
    assert job.world.dump() == CELL.read_text()


def test_frame_block_made_online_looks_the_same_offline() -> None:
    edited = ("MOVE ARM TO pos0\nFRAME base_plate\n    MOVE ARM TO pos1\nENDFRAME\nFRAME base_plate\n    MOVE ARM TO pos2\n"
              "ENDFRAME\nMOVE ARM TO pos3\n")
    assert print_offline(back(edited).program) == PROGRAM


def test_online_frame_retaught_moves_the_plate_relative_to_its_fixture() -> None:
    edited = online_text().replace("FRAME base_plate = POSE(1000mm, 100mm, 620mm", "FRAME base_plate = POSE(1000mm, 100mm, 625mm")
    assert changed_lines(CELL.read_text(), back(edited).world.dump()) == [
        ("    pose: [0, 0, 20mm, 0, 0, 0]", "    pose: [0, 0, 25mm, 0, 0, 0]")]


def test_tool_measured_online_changes_the_last_link_of_the_chain() -> None:
    program = "move grinder to pos0\n"
    text = print_program(to_online(parse_offline(program), load_world(CELL)).program)
    assert text.startswith("TOOL grinder = POSE(20mm, 0, 180mm, 0, 0, 0)\n")
    job = back(text.replace("TOOL grinder = POSE(20mm, 0, 180mm", "TOOL grinder = POSE(20mm, 0, 185mm"))
    assert changed_lines(CELL.read_text(), job.world.dump()) == [
        ("    pose: [20mm, 0, 120mm, 0, 0, 0]", "    pose: [20mm, 0, 125mm, 0, 0, 0]")]
    assert print_offline(job.program) == program
