"""Each pass of the transformation, before and after, on the test cell (nested frames, a clash, a tool chain)."""

from __future__ import annotations

import pytest

from orc_rpl.errors import SourceError
from orc_rpl.transform.declarations import absorb_declarations, collapse_tools, declare_frames, declare_positions
from orc_rpl.transform.frames import insert_frame_blocks, remove_frame_blocks
from orc_rpl.transform.naming import name_world
from orc_rpl.transform.pipeline import reduce_world, refuse_clashes, restore_world
from orc_rpl.transform.references import resolve_positions, unresolve_positions
from tests.transform.helpers import nested, offline, offline_job, online, online_job


def resolved(text: str):  # type: ignore[no-untyped-def]
    return resolve_positions(offline_job(text))


def test_names_are_short_unless_the_world_has_the_name_twice() -> None:
    names = name_world(nested())
    assert names.online["base_plate.pos1"] == "pos1"
    assert names.online["clamp.grip"] == "grip"
    assert (names.online["fixture_a.p"], names.online["fixture_b.p"]) == ("fixture_a_p", "fixture_b_p")
    assert names.entity["fixture_b_p"] == "fixture_b.p"
    assert names.online["grinder"] == "grinder"


def test_resolve_positions_names_world_paths_on_line() -> None:
    job = resolved("moveto base_plate.pos1\nmove grinder to fixture_b.p via home\nn = fixture_b.done\n")
    assert online(job) == "MOVE ARM TO pos1\nMOVE grinder TO fixture_b_p VIA home\nn = fixture_b.done\n"
    assert job.used == ("base_plate.pos1", "grinder", "fixture_b.p", "home")
    assert dict(job.chains) == {"pos1": ("base_plate",), "fixture_b_p": (), "home": ()}


def test_resolve_positions_refuses_an_unknown_world_path_at_its_column() -> None:
    with pytest.raises(SourceError) as caught:
        resolved("moveto base_plate.pos1\nmoveto base_plate.pos9\n")
    text = caught.value.format()
    assert text.startswith("test.orl:2:19: 'base_plate' has no frame, path or attribute 'pos9'")
    assert "did you mean 'pos1'?" in text


def test_refuse_clashes_refuses_a_program_name_that_the_world_names() -> None:
    with pytest.raises(SourceError, match=r"test.orl:1:5: 'pos1' is declared in the program and is also 'base_plate.pos1'"):
        refuse_clashes(offline_job("pos pos1 = POSE(0, 0, 0, 0, 0, 0)\nmoveto base_plate.pos1\n"))


def test_insert_frame_blocks_wraps_first_to_last_use_and_nests() -> None:
    job = resolved("moveto home\nmoveto base_plate.above\nwait 1s\nmoveto clamp.grip\nmoveto base_plate.pos1\n"
                   "# done\nmoveto home\n")
    assert online(insert_frame_blocks(job)) == (
        "MOVE ARM TO home\n"
        "FRAME base_plate\n"
        "    MOVE ARM TO above\n"
        "    WAIT 1s\n"
        "    FRAME clamp\n"
        "        MOVE ARM TO grip\n"
        "    ENDFRAME\n"
        "    MOVE ARM TO pos1\n"
        "ENDFRAME\n"
        "-- done\n"
        "MOVE ARM TO home\n")


def test_insert_frame_blocks_wraps_a_whole_loop_or_goes_inside_a_mixed_one() -> None:
    job = resolved("for i in 1..3:\n    moveto base_plate.pos1\nwhile x:\n    moveto home\n    moveto base_plate.pos1\n")
    assert online(insert_frame_blocks(job)) == (
        "FRAME base_plate\n"
        "    FOR i FROM 1 TO 3 DO\n"
        "        MOVE ARM TO pos1\n"
        "    ENDFOR\n"
        "ENDFRAME\n"
        "WHILE x DO\n"
        "    MOVE ARM TO home\n"
        "    FRAME base_plate\n"
        "        MOVE ARM TO pos1\n"
        "    ENDFRAME\n"
        "ENDWHILE\n")


def test_declare_positions_declares_each_position_and_path_in_its_frame() -> None:
    job = declare_positions(resolved("# cell\nmoveto clamp.grip\ngrindmove grinder along fixture_b.seam\n"))
    assert online(job) == (
        "-- cell\n"
        "POS grip = POSE(0, 0, 50mm, 0, 180deg, 0) IN clamp\n"
        "PATH seam = [POSE(1200mm, 0, 700mm, 0, 180deg, 0), POSE(1210mm, 0, 700mm, 0, 180deg, 0)]\n"
        "MOVE ARM TO grip\n"
        "GRINDMOVE grinder ALONG seam\n")


def test_collapse_tools_makes_one_tool_of_the_holder_and_the_grinder() -> None:
    job = collapse_tools(resolved("move grinder to home\n"))
    assert online(job).splitlines()[0] == "TOOL grinder = POSE(20mm, 0, 180mm, 0, 0, 0)"


def test_declare_frames_declares_outer_frames_first() -> None:
    job = declare_frames(resolved("moveto clamp.grip\n"))
    assert online(job).splitlines()[:2] == ["FRAME base_plate = POSE(1000mm, 0, 620mm, 90deg, 0, 0)",
                                           "FRAME clamp = POSE(0, 200mm, 0, 0, 0, 0) IN base_plate"]


def test_reduce_world_replaces_model_attributes_by_keys_and_restore_world_gives_them_back() -> None:
    job = reduce_world(offline_job("moveto home\n"))
    text = job.world.dump()
    assert "model_key: table" in text and "geometry: box" not in text
    assert restore_world(job).world.dump() == nested().dump()


def test_absorb_declarations_puts_a_taught_position_into_its_frame() -> None:
    job = absorb_declarations(online_job("POS pos1b = POSE(60mm, -40mm, 60mm, 0, 180deg, 0) IN base_plate\nMOVE ARM TO pos1b\n"))
    assert online(job) == "MOVE ARM TO pos1b\n"
    assert "      pos1b: [60mm, -40mm, 60mm, 0, 180deg, 0]\n" in job.world.dump()
    assert "base_plate.pos1b" in job.used


def test_absorb_declarations_touches_up_a_changed_position_and_keeps_an_unchanged_one() -> None:
    job = absorb_declarations(online_job("POS pos1 = POSE(55mm, -40mm, 60mm, 0, 180deg, 0) IN base_plate\n"
                                         "POS home = POSE(800mm, 0, 900mm, 0, 180deg, 0)\n"))
    before, after = nested().dump().splitlines(), job.world.dump().splitlines()
    assert [(a, b) for a, b in zip(before, after) if a != b] == [
        ("      pos1: [50mm, -40mm, 60mm, 0, 180deg, 0]", "      pos1: [55mm, -40mm, 60mm, 0, 180deg, 0]")]


def test_remove_frame_blocks_splices_the_blocks_of_world_frames() -> None:
    job = remove_frame_blocks(online_job("FRAME base_plate\n    MOVE ARM TO pos1\n    FRAME clamp\n        MOVE ARM TO grip\n"
                                         "    ENDFRAME\nENDFRAME\nFRAME other\n    MOVE ARM TO q\nENDFRAME\n"))
    assert online(job) == "MOVE ARM TO pos1\nMOVE ARM TO grip\nFRAME other\n    MOVE ARM TO q\nENDFRAME\n"


def test_unresolve_positions_gives_world_paths_back() -> None:
    job = online_job("MOVE grinder TO fixture_a_p\nMOVE ARM TO pos1\n")
    job = unresolve_positions(job.__class__(job.program, job.world, used=("fixture_a.p", "base_plate.pos1", "grinder")))
    assert offline(job) == "move grinder to fixture_a.p\nmoveto base_plate.pos1\n"
