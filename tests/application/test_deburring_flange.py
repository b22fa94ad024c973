"""GRINDMOVE with an installed Grinder's force flange, and the casting's contact force acting on the arm."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from orc_rpl.cli import main
from orc_rpl.executive.cell_robot import CellRobot
from orc_rpl.plant.processes.casting import Bulge, CastingEdge
from orc_rpl.world.pose import Pose

ROOT = Path(__file__).resolve().parents[2]
THESIS = ROOT / "programs/online/thesis_2_1_grindmove.rpl"
GRINDER = "INSTALL grinder AS Grinder WITH SPINDLE = DigOut[5]{flange}\n"


def run(tmp_path: Path, flange: str, capsys: pytest.CaptureFixture[str]) -> tuple[int, str, dict]:
    """`orc run` of thesis_2_1_grindmove.rpl, its Grinder given `flange` (its casting beside it)."""
    source = THESIS.read_text(encoding="utf-8")
    program = tmp_path / THESIS.name
    assert GRINDER.format(flange="") in source
    program.write_text(source.replace(GRINDER.format(flange=""), GRINDER.format(flange=flange)), encoding="utf-8")
    program.with_suffix(".sim.yaml").write_text(THESIS.with_suffix(".sim.yaml").read_text(encoding="utf-8"))
    summary = tmp_path / "summary.json"
    code = main(["run", str(program), "--summary-json", str(summary), "--plant", "ideal"])
    out, err = capsys.readouterr()
    return code, out + err, json.loads(summary.read_text()) if summary.exists() else {}


@pytest.mark.sim
def test_a_grinder_with_a_force_flange_grinds_the_bulge(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, output, summary = run(tmp_path, " WITH FORCE_IN = AnalogIn[8] WITH STROKE = AnalogOut[8]", capsys)
    assert code == 0, output
    (bulge,) = summary["process"]["bulges"]
    assert bulge["within_tolerance"] and bulge["left_m"] <= 0.0002


@pytest.mark.sim
def test_a_flange_on_other_channels_is_not_read_where_the_casting_writes(tmp_path: Path,
                                                                          capsys: pytest.CaptureFixture[str]) -> None:
    code, output, _ = run(tmp_path, " WITH FORCE_IN = AnalogIn[3] WITH STROKE = AnalogOut[3]", capsys)
    assert code == 0, output  # the casting's force is on AnalogIn[8]: the flange on [3] never feels it
    assert "no contact force on AnalogIn[3]" in output


def test_half_a_force_flange_is_a_clear_error(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, output, _ = run(tmp_path, " WITH FORCE_IN = AnalogIn[8]", capsys)
    assert code == 1
    assert "a force flange needs both FORCE_IN = AnalogIn[n] and STROKE = AnalogOut[n]" in output
    assert "Traceback" not in output


@pytest.mark.sim
def test_the_arm_feels_the_casting_it_presses_on() -> None:
    """A bulge 1 mm into the resting TCP pushes 50 N up on the arm: the motor torques change by about
    J^T F (the ideal plant, whose model is exact)."""
    robot = CellRobot.virtual(plant="ideal")
    tool = Pose(0.0, 0.0, 0.15)
    for _ in range(100):
        robot.tick()
    tcp = robot.tcp_pose(tool)
    edge = [(tcp.x, tcp.y - 0.1, tcp.z), (tcp.x, tcp.y + 0.1, tcp.z)]
    before = np.array(robot.torques())
    casting = CastingEdge(edge, [Bulge(0.05, 0.15, 0.001)], tcp=lambda: robot.tcp_pose(tool),
                          push=robot.push_on_arm)
    robot.io.add_process(casting)
    for _ in range(250):  # 1 s: the servo's integral takes the push up
        robot.tick()
    assert casting.force_n == pytest.approx(casting.stiffness_n_m * 0.001, rel=0.05)
    expected = robot.jacobian_linear(tool).T @ np.array((0.0, 0.0, casting.force_n))
    change = before - np.array(robot.torques())
    assert np.abs(expected).max() > 10.0
    assert np.allclose(change, expected, atol=0.1 * np.abs(expected).max()), (change, expected)
    assert not math.isnan(change.sum())

