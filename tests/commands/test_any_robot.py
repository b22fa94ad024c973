"""Programs are robot-independent: the shared-workspace demo runs unchanged on both robot models."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from orc_rpl.cli import main

DEMO = Path(__file__).resolve().parents[2] / "programs" / "online" / "demo_any_robot.rpl"


@pytest.mark.parametrize("robot", ["irb2400", "ur5e"])
def test_same_program_runs_on_every_robot(robot: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    summary = tmp_path / "summary.json"
    assert main(["run", str(DEMO), "--robot", robot, "--summary-json", str(summary)]) == 0
    report = json.loads(summary.read_text())
    assert report["status"] == "finished" and report["motions"] == 14
    assert report["prints"] == ["moved 2 parts; TCP z above the tray: 0.2 m"]
    tcp = report["final_tcp"]
    assert (tcp["x_m"], tcp["y_m"], tcp["z_m"]) == pytest.approx((0.6, 0.0, 0.5), abs=5e-4), "ends above the tray"
