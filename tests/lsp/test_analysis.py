"""What the server knows about a document: its diagnostics, the world an off-line program names, names despite a bad line."""

from __future__ import annotations

from pathlib import Path

from orc_rpl.application.registry import default_registry
from orc_rpl.lsp.analysis import analyse
from orc_rpl.lsp.index import ProgramIndex

REGISTRY = default_registry()


def test_a_missing_world_file_is_reported_on_the_world_line(tmp_path: Path) -> None:
    path = str(tmp_path / "prog.orl")
    analysis = analyse("# world: nowhere.yaml\nmoveto pos0\n", path, REGISTRY)
    [diagnostic] = analysis.diagnostics
    location = diagnostic.location
    assert (location.path, location.line, location.column, location.end_line, location.end_column) == (path, 1, 1, 1, 22)
    assert diagnostic.message == f"world model '{tmp_path / 'nowhere.yaml'}' does not exist"
    assert analysis.program is not None and analysis.world is None


def test_without_a_world_line_only_the_syntax_of_an_offline_program_is_checked(tmp_path: Path) -> None:
    analysis = analyse("moveto base_plate.nothing\n", str(tmp_path / "prog.orl"), REGISTRY)
    assert analysis.diagnostics == [] and analysis.world is None


def test_names_declared_elsewhere_stay_known_while_a_line_does_not_parse(tmp_path: Path) -> None:
    text = "POS p1 = POSE(1m, 0, 1m, 0, 180deg, 0)\nMOVE ARM TO\nPROC Go(q)\n  MOVE ARM TO q\nENDPROC\n"
    analysis = analyse(text, str(tmp_path / "prog.rpl"), REGISTRY)
    assert analysis.program is None and [d.location.line for d in analysis.diagnostics] == [2]
    assert analysis.salvaged is not None
    assert {"p1", "Go"} <= set(ProgramIndex(analysis.salvaged).globals)


def test_an_online_program_may_name_the_moving_frames_of_the_cell_its_world_line_names() -> None:
    path = Path(__file__).resolve().parents[2] / "programs" / "online" / "demo_positioner.rpl"
    text = path.read_text(encoding="utf-8")
    assert analyse(text, str(path), REGISTRY).diagnostics == []
    # without its `-- world:` line the same program names a frame nobody declared
    (diagnostic,) = analyse(text.split("\n", 1)[1], str(path), REGISTRY).diagnostics
    assert "unknown frame 'turn'" in diagnostic.message and diagnostic.location.line == 11
