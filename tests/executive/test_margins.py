"""`orc run --margins`: clearance and joint margins per motion statement, measured in the cell the program runs in."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from orc_rpl.cli import main
from tests.plant.test_world_scene import WORLD

#: Down to 80 mm above the block (line 5), back up, onto the part the robot works on (line 7), back up.
PROGRAM = """\
POS above = POSE(900mm, 0, 800mm, 0, 180deg, 0)
POS near = POSE(900mm, 0, 560mm, 0, 180deg, 0)
POS on_part = POSE(900mm, 400mm, 440mm, 0, 180deg, 0)
MOVE ARM TO above
LMOVE ARM TO near WITH SPEED = 0.2mps
LMOVE ARM TO above
LMOVE ARM TO on_part WITH SPEED = 0.2mps
LMOVE ARM TO above
"""


def _run(tmp_path: Path, *extra: str) -> tuple[int, dict]:
    summary = tmp_path / f"summary{len(extra)}.json"
    code = main(["run", str(tmp_path / "prog.rpl"), "--world", str(tmp_path / "cell.yaml"),
                 "--summary-json", str(summary), *extra])
    return code, json.loads(summary.read_text())


@pytest.mark.sim
def test_margins_are_measured_per_motion_statement_in_the_world_cell_and_change_nothing(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "cell.yaml").write_text(WORLD)
    (tmp_path / "prog.rpl").write_text(PROGRAM)
    code, plain = _run(tmp_path)
    code_m, measured = _run(tmp_path, "--margins")
    assert code == code_m == 0
    margins = measured.pop("margins")
    assert measured == plain, "measuring the margins leaves the run exactly as it was"
    by_line = {m["line"]: m for m in margins["motions"]}
    assert sorted(by_line) == [4, 5, 6, 7, 8]
    assert all(m["obstacle"] == "block" for m in by_line.values()), "the part is the robot's work: no obstacle"
    assert 75.0 < by_line[5]["clearance_mm"] < 85.0 and by_line[4]["clearance_mm"] > 200.0
    nearest = margins["clearance"]
    assert nearest["line"] in (5, 6) and nearest["clearance_mm"] == min(m["clearance_mm"] for m in by_line.values())
    assert (nearest["robot_body"], nearest["obstacle"]) == ("link5", "block")
    assert margins["joint_margin"]["joint_margin_deg"] == min(m["joint_margin_deg"] for m in by_line.values())
    assert margins["rate_hz"] == 250.0 and 0 < margins["measured"] < margins["samples"]
    err = capsys.readouterr().err
    assert f"margins: clearance: {nearest['clearance_mm']:.1f} mm, link5 to block" in err
    assert f"prog.rpl:{nearest['line']})" in err


def test_margins_need_the_simulated_cell(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "prog.rpl").write_text(PROGRAM)
    assert main(["run", str(tmp_path / "prog.rpl"), "--margins", "--port", "/dev/null", "--robot", "so101"]) == 2
    assert "--margins: only a run on the simulated cell measures its margins" in capsys.readouterr().err
