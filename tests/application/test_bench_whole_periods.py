"""bench_applications --whole-periods: the elastic gears' cells, its own and `orc run`'s, average over the whole periods."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

import orc_rpl.motion
from benchmarks import bench_applications
from orc_rpl.executive.cell_robot import CellRobot

PROGRAM = """TOOL effector = POSE(0, 0, 200mm, 0, 0, 0)
MOVE effector TO POSE(900mm, 200mm, 800mm, 0, 180deg, 0)
"""


@pytest.fixture
def restored(monkeypatch: pytest.MonkeyPatch) -> None:
    """The motion layer's maker put back after the test (use_whole_periods replaces it)."""
    monkeypatch.setattr(orc_rpl.motion, "make_virtual_motion_layer", orc_rpl.motion.make_virtual_motion_layer)


def test_whole_periods_reach_the_elastic_gears_cells_only(restored: None) -> None:
    assert CellRobot.virtual(plant="elastic-gears").layer.planner.gear_steps is not None   # the default: scaled
    bench_applications.use_whole_periods()
    assert CellRobot.virtual(plant="elastic-gears").layer.planner.gear_steps is None
    assert CellRobot.virtual(plant="realistic").layer.planner.gear_steps is None       # rigid gears: nothing to scale


def test_orc_run_by_default_ends_a_gentle_move_sooner_than_with_whole_periods(tmp_path: Path) -> None:
    program = tmp_path / "move.rpl"
    program.write_text(PROGRAM, encoding="utf-8")

    def cycle_s(orc: list[str]) -> float:
        summary = tmp_path / "summary.json"
        subprocess.run([sys.executable, *orc, "run", str(program), "--plant", "elastic-gears",
                        "--summary-json", str(summary)], check=True, capture_output=True)
        return float(json.loads(summary.read_text())["cycle_time_s"])
    scaled, whole = cycle_s(["-m", "orc_rpl"]), cycle_s(["-c", bench_applications.ORC_RUN_WHOLE])
    assert scaled < whole - 0.05   # the whole periods add 0.295 s to the move; a gentle move's steps call for less
