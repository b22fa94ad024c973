"""KNOWN: what the program knows about a motion decides how it is planned (checked, run, reported)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from orc_rpl.cli import main
from orc_rpl.motion import CartesianMotion, Computation, Params, make_virtual_motion_layer
from orc_rpl.world.pose import Pose

POSITIONS = """\
POS p1 = POSE(800mm, -300mm, 900mm, 0, 180deg, 0)
POS p2 = POSE(1100mm, -200mm, 800mm, 0, 180deg, 0)
POS p3 = POSE(900mm, 200mm, 850mm, 0, 180deg, 0)
"""


def run(tmp_path: Path, capsys: pytest.CaptureFixture[str], body: str) -> tuple[dict, str]:
    program = tmp_path / "prog.rpl"
    program.write_text(POSITIONS + body)
    summary = tmp_path / "summary.json"
    code = main(["run", str(program), "--plant", "ideal", "--summary-json", str(summary)])
    err = capsys.readouterr().err
    assert code == 0, err
    return json.loads(summary.read_text()), err


def test_an_unknown_value_of_known_is_a_check_error_at_its_column(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    program = tmp_path / "prog.rpl"
    program.write_text(POSITIONS + 'MOVE ARM TO p1 WITH KNOWN = "mostly"\n')
    assert main(["check", str(program)]) == 2
    out = capsys.readouterr().out
    assert f'{program}:4:29: attribute KNOWN of MOVE: KNOWN must be "completely", "almost", "partly" or "not", got "mostly"' in out


def test_fine_motions_are_planned_while_the_one_before_runs(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    result, err = run(tmp_path, capsys, "MOVE ARM TO p1\nMOVE ARM TO p2\nLMOVE ARM TO p3\nMOVE ARM TO p1\n")
    assert result["planning"] == {"planned_ahead": 3, "reused": 3, "replanned": 0, "at_start": 1}
    assert "planning: 3 motions planned ahead (3 plans used, 0 made again), 1 planned when they started" in err


def test_partly_and_not_known_motions_are_planned_when_they_start(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    result, _ = run(tmp_path, capsys, 'MOVE ARM TO p1\nMOVE ARM TO p2 WITH KNOWN = "partly"\n'
                                      'MOVE ARM TO p3 WITH KNOWN = "not"\nMOVE ARM TO p1 WITH KNOWN = "almost"\n')
    assert result["planning"] == {"planned_ahead": 1, "reused": 1, "replanned": 0, "at_start": 3}


def _one_motion_s(tmp_path: Path, capsys: pytest.CaptureFixture[str], known: str) -> float:
    first, _ = run(tmp_path, capsys, "MOVE ARM TO p1\n")
    both, _ = run(tmp_path, capsys, f'MOVE ARM TO p1\nMOVE ARM TO p2 WITH KNOWN = "{known}"\n')
    return both["cycle_time_s"] - first["cycle_time_s"]


def test_each_degree_of_knowledge_plans_differently(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Completely known: the full limits; almost: some left for sensor corrections; partly: a nominal path at half
    the limits; not: generated at run time (jerk-limited, no time-optimal path)."""
    seconds = {known: _one_motion_s(tmp_path, capsys, known) for known in ("completely", "almost", "partly", "not")}
    assert seconds["completely"] < seconds["almost"] < seconds["partly"]
    assert seconds["not"] != seconds["completely"], seconds  # another trajectory, not the time-optimal one


def test_a_plan_made_for_another_motion_is_not_used() -> None:
    """The program's knowledge proved wrong (thesis 5.2: start and target are compared): the move is planned again."""
    layer = make_virtual_motion_layer(backend="kinematic")
    home = Pose.from_matrix(layer.tcp_pose())
    predicted = CartesianMotion(target=Pose(home.x + 0.1, home.y, home.z, home.a, home.b, home.c), kind="joint")
    actual = CartesianMotion(target=Pose(home.x, home.y + 0.1, home.z, home.a, home.b, home.c), kind="joint")
    descriptor = layer.plan_ahead(predicted)
    assert descriptor is not None
    handle = layer.move(actual, Params(computation=Computation.DONE, descriptor=descriptor))
    assert layer.run_until_idle(10.0) and handle.replanned_during
    assert np.allclose(layer.tcp_pose()[:3, 3], [home.x, home.y + 0.1, home.z], atol=1e-4)
    assert layer.ahead is not None and (layer.ahead.counts.replanned, layer.ahead.counts.reused) == (1, 0)
    again = layer.plan_ahead(predicted)
    assert again is not None
    layer.move(CartesianMotion(target=home, kind="joint"))  # a move the prediction did not know of comes first
    layer.move(predicted, Params(computation=Computation.DONE, descriptor=again))
    assert layer.run_until_idle(10.0)
    assert (layer.ahead.counts.replanned, layer.ahead.counts.reused) == (2, 0)  # it starts elsewhere than planned
    assert np.allclose(layer.tcp_pose()[:3, 3], [home.x + 0.1, home.y, home.z], atol=1e-4)
