"""The one way a measured pose is shown to people: `shown_pose`, and `orc run` and `orc diff` using it."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from orc_rpl.cli import main
from orc_rpl.world.pose import Pose, matrix, shown_pose


def measured(a_deg: float, b_deg: float, c_deg: float) -> Pose:
    """A pose written with these angles, as the controller measures it back (through its matrix)."""
    return Pose.from_matrix(matrix(1.0, -1e-9, 0.8, *(math.radians(v) for v in (a_deg, b_deg, c_deg))))


@pytest.mark.parametrize("written, shown", [
    pytest.param((0, 180, 0), (0.0, 180.0, 0.0), id="tool-down-keeps-its-spelling"),
    pytest.param((180, 0, 180), (0.0, 180.0, 0.0), id="the-other-triple-of-tool-down-shows-the-same"),
    pytest.param((-90, 180, 0), (-90.0, 180.0, 0.0), id="turned-tool-down-keeps-c-zero"),
    pytest.param((0, 0, 180), (0.0, 0.0, 180.0), id="one-turn-about-x"),
    pytest.param((30, 180, 0), (30.0, 180.0, 0.0), id="fewest-angles-then-smaller-c"),
    pytest.param((10, 20, 30), (10.0, 20.0, 30.0), id="a-general-rotation-as-written"),
    pytest.param((-180, 0, 0), (180.0, 0.0, 0.0), id="minus-180-is-shown-as-180"),
    pytest.param((-179.99, 0, 0), (180.0, 0.0, 0.0), id="rounds-to-minus-180-shown-as-180"),
])
def test_shown_pose_picks_the_documented_triple(written: tuple[float, float, float], shown: tuple[float, float, float]) -> None:
    result = shown_pose(measured(*written))
    assert (result.a_deg, result.b_deg, result.c_deg) == shown
    assert (result.x_mm, result.y_mm, result.z_mm) == (1000.0, 0.0, 800.0)


def test_shown_pose_never_writes_minus_zero() -> None:
    text = shown_pose(measured(0, 180, 0)).text()
    assert text == "(1000.0, 0.0, 800.0) mm, (0.0, 180.0, 0.0) deg"
    assert "-0.0" not in shown_pose(Pose(-1e-7, -4e-5, 0.0, -1e-9, -1e-9, -1e-9)).text()


def test_shown_pose_keeps_more_digits_when_asked() -> None:
    assert shown_pose(measured(-179.99, 0, 0), mm_digits=3, deg_digits=3).text() == \
        "(1000.000, 0.000, 800.000) mm, (-179.990, 0.000, 0.000) deg"


@pytest.mark.sim
def test_run_summary_shows_a_tool_down_pose_as_declared(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    program = tmp_path / "down.rpl"
    program.write_text("POS p = POSE(1000mm, 0, 800mm, 0, 180deg, 0)\nMOVE ARM TO p\n")
    assert main(["run", str(program)]) == 0
    err = capsys.readouterr().err
    assert "final TCP: (1000.0, 0.0, 800.0) mm, (0.0, 180.0, 0.0) deg" in err


def test_diff_treats_two_spellings_of_one_pose_as_the_same(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "a.rpl").write_text("POS p = POSE(1000mm, 0, 800mm, 0, 180deg, 0)\nMOVE ARM TO p\n")
    (tmp_path / "b.rpl").write_text("POS p = POSE(1000mm, 0, 800mm, 180deg, 0, 180deg)\nMOVE ARM TO p\n")
    assert main(["diff", str(tmp_path / "a.rpl"), str(tmp_path / "b.rpl")]) == 0
    assert capsys.readouterr().out == ""


def test_diff_shows_a_changed_pose_in_the_display_convention(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "a.rpl").write_text("FRAME f = POSE(0, 0, 0, 0, 0, 0)\nPOS p = POSE(50mm, 0, 60mm, 0, 180deg, 0) IN f\n")
    (tmp_path / "b.rpl").write_text("FRAME f = POSE(0, 0, 0, 0, 0, 0)\nPOS p = POSE(50mm, 0, 60mm, -180deg, 0, -180deg) IN f\n"
                                    .replace("50mm", "51mm"))
    assert main(["diff", str(tmp_path / "a.rpl"), str(tmp_path / "b.rpl")]) == 1
    out = capsys.readouterr().out
    assert "~ POS p changed: POSE(50mm, 0, 60mm, 0, 180deg, 0) IN f -> POSE(51mm, 0, 60mm, -180deg, 0, -180deg) IN f" in out
    assert "    (50.0, 0.0, 60.0) mm, (0.0, 180.0, 0.0) deg -> (51.0, 0.0, 60.0) mm, (0.0, 180.0, 0.0) deg in f" in out
