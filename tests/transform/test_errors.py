"""What the transformation refuses, and how it says so: file:line:col for program mistakes, the entity for world ones."""

from __future__ import annotations

import pytest

from orc_rpl.errors import OrcError, SourceError
from orc_rpl.syntax.offline_parser import parse_offline
from orc_rpl.syntax.offline_printer import print_offline
from orc_rpl.syntax.parser import parse
from orc_rpl.syntax.printer import print_program
from orc_rpl.transform.pipeline import to_offline, to_online
from orc_rpl.transform.references import world_diagnostics
from orc_rpl.world.pose import Pose
from tests.transform.helpers import nested


def test_check_reports_unknown_world_paths_and_indices_at_their_columns() -> None:
    program = parse_offline("moveto fixture_b.q\nmoveto fixture_b.seam[3]\nmoveto fixture_b.seam[2]\n", "p.orl")
    found = [(d.location.line, d.location.column, d.message, d.hint) for d in world_diagnostics(program, nested(), "p.orl")]
    assert found[0][:2] == (1, 18) and "'fixture_b' has no frame, path or attribute 'q'" in found[0][2]
    assert found[1] == (2, 23, "index 3 is outside 1..2 of path 'fixture_b.seam'", "")
    assert len(found) == 2


def test_a_program_variable_shadows_a_world_object() -> None:
    program = parse_offline("home = 3\nprint(home)\nmoveto base_plate.pos1\n")
    text = print_program(to_online(program, nested()).program)
    assert "POS home" not in text and "PRINT home\n" in text


def test_an_online_name_the_program_uses_otherwise_is_refused() -> None:
    with pytest.raises(OrcError, match="'base_plate.pos1' is named 'pos1' on-line, which the program uses for something else"):
        to_online(parse_offline("pos1 = 3\nmoveto base_plate.pos1\n"), nested())


def test_a_program_position_in_a_world_frame_is_refused_at_its_column() -> None:
    with pytest.raises(SourceError, match=r"p.orl:1:39: positions relative to the world's frame 'clamp' belong in the world model"):
        to_online(parse_offline("pos extra = POSE(0, 0, 0, 0, 0, 0) in clamp\n", "p.orl"), nested(), "p.orl")


def test_a_path_changed_online_is_refused_with_its_entity() -> None:
    text = print_program(to_online(parse_offline("grindmove grinder along fixture_b.seam\n"), nested()).program)
    edited = text.replace("POSE(1210mm", "POSE(1215mm")
    with pytest.raises(OrcError, match="path 'seam' was changed on-line; edit 'fixture_b.seam' in the world model"):
        to_offline(parse(edited), nested())


def test_clashing_frame_names_go_online_qualified_and_come_back() -> None:
    source = "moveto fixture_a.p\nmoveto fixture_b.p\n"
    text = print_program(to_online(parse_offline(source), nested()).program)
    assert "MOVE ARM TO fixture_a_p\nMOVE ARM TO fixture_b_p\n" in text
    job = to_offline(parse(text), nested())
    assert print_offline(job.program) == source and job.world.dump() == nested().dump()


def test_an_undeclared_name_that_is_a_frames_online_name_is_refused() -> None:
    with pytest.raises(SourceError, match=r"p.orl:1:7: 'grip' is the on-line name of 'clamp.grip' of the world model"):
        to_online(parse_offline("print(grip)\n", "p.orl"), nested(), "p.orl")



@pytest.mark.parametrize(("text", "line", "column"), [
    ("moveto camera\n", 1, 8),                    # the object itself, as a position
    ("moveto camera.lens\n", 1, 8),               # its frame: where that is, too, is the flange's business
    ("install camera as SpotGun close=DigOut[3] weld_ok=DigIn[2] reaction=80ms\nmove camera to fixture_b.p\n", 2, 6),
])
def test_an_object_on_the_flange_that_is_not_a_tool_is_refused_at_its_first_use(text: str, line: int, column: int) -> None:
    world = nested().with_object("camera", "flange").with_frame("camera", "lens", Pose(0, 0, 0.05, frame="camera"))
    program = parse_offline(text, "p.orl")
    found = world_diagnostics(program, world, "p.orl")
    assert [(d.location.line, d.location.column) for d in found] == [(line, column)]
    assert "'camera' hangs on the flange" in found[0].message and "tool: true" in found[0].hint
    with pytest.raises(SourceError, match=rf"p.orl:{line}:{column}: 'camera' hangs on the flange"):
        to_online(program, world, "p.orl")
