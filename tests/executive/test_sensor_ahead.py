"""Motions computed ahead from sensor dummies (thesis 5.2): planned before the real sensor answered, then confirmed or
corrected by its answer, through `orc run` and the executive."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from orc_rpl.cli import main
from orc_rpl.executive.cell_robot import CellRobot
from orc_rpl.executive.executive import Executive
from orc_rpl.motion.sensors import LaserValue
from orc_rpl.syntax.parser import parse

ROOT = Path(__file__).resolve().parents[2]
DEMO = ROOT / "programs/online/demo_sensor_ahead.rpl"


def orc_run(program: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> tuple[list[str], str, dict]:
    summary = tmp_path / "summary.json"
    code = main(["run", str(program), "--summary-json", str(summary), "--sim", str(DEMO.with_suffix(".sim.yaml"))])
    out, err = capsys.readouterr()
    assert code == 0, err
    return out.splitlines(), err, json.loads(summary.read_text())["planning"]


def on_seam_mm(lines: list[str]) -> list[float]:
    """What the laser reads on the seam after each approach (mm from the beam)."""
    return [float(line.split("sees it ")[1].split(" mm")[0]) for line in lines if line.startswith("on the seam")]


@pytest.mark.sim
def test_the_approach_is_planned_from_the_dummy_and_corrected_by_the_laser(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    lines, err, planning = orc_run(DEMO, tmp_path, capsys)
    # both approaches to the seam were planned while the robot moved above it, from the dummy (0 mm), and the
    # laser's answer (the seam 3.9 mm from the beam) corrected them along the motion: the torch ends on the seam
    assert planning["from_dummy"] == 2 and planning["corrected"] == 2 and planning["confirmed"] == 0, planning
    assert planning["reused"] >= 2 and planning["replanned"] == 0, planning
    assert "2 motions computed ahead from sensor dummies, before the sensor answered (0 confirmed, 2 corrected" in err
    seam = on_seam_mm(lines)
    assert len(seam) == 2 and all(abs(v) < 0.1 for v in seam), lines
    # without a dummy value the dummy sees no seam: the approach is planned when the laser has answered, and ends
    # where the corrected plan ended
    plain = tmp_path / "plain.rpl"
    plain.write_text(DEMO.read_text().replace(" WITH DUMMY = 0mm", ""))
    lines_plain, err_plain, planning_plain = orc_run(plain, tmp_path, capsys)
    assert "from_dummy" not in planning_plain and planning_plain["planned_ahead"] == 0, planning_plain
    assert "sensor dummies" not in err_plain
    assert all(abs(a - b) < 0.05 for a, b in zip(on_seam_mm(lines_plain), seam)), (lines_plain, lines)


SOURCE = """
TOOL torch = POSE(0, 0, 200mm, 0, 0, 0)
INSTALL LaserSensor AS LaserDistance WITH PORT = "sim" WITH DUMMY = {dummy}
POS Above = POSE(1000mm, -200mm, 600mm, 0, 180deg, 0)
POS OnSeam = POSE(1000mm, -200mm, 500mm, 0, 180deg, 0)
LaserSensor.On
MOVE torch TO Above
MOVE torch TO OFFS(OnSeam, LaserSensor.Distance, 0, 0) WITH KNOWN = "{known}"
PRINT HERE.x / 1mm
"""


def run_with_laser(dummy: str, seen_m: float, known: str = "almost") -> tuple[Executive, CellRobot]:
    """The program above on the simulated cell, the laser always reading the seam `seen_m` from the beam."""
    robot = CellRobot.virtual()
    robot.sensors.simulations["LaserDistance"] = lambda name: (lambda sensor: LaserValue(True, seen_m, False))
    text = SOURCE.format(dummy=dummy, known=known)
    executive = Executive(parse(text, "ahead.rpl"), robot, path="ahead.rpl", source=text, output=lambda line: None)
    executive.run()
    assert executive.status == "finished", executive.report()
    return executive, robot


@pytest.mark.sim
def test_a_laser_that_answers_the_dummy_value_confirms_the_plan() -> None:
    executive, robot = run_with_laser("3mm", 0.003)
    counts = robot.planning
    assert (counts.from_dummy, counts.confirmed, counts.corrected, counts.replanned) == (1, 1, 0, 0)
    assert abs(float(executive.prints[-1]) - 1003.0) < 0.1, executive.prints
    # the prediction asked the dummy, never the laser: the laser was read once, when the statement ran
    assert robot.sensors.pairs["LaserSensor"].sensor.samples == 1


@pytest.mark.sim
def test_an_answer_far_from_the_dummy_is_planned_again_and_still_reached() -> None:
    executive, robot = run_with_laser("30mm", 0.004)   # 26 mm off the dummy: more than a correction
    counts = robot.planning
    assert (counts.from_dummy, counts.confirmed, counts.corrected, counts.replanned) == (1, 0, 0, 1)
    assert abs(float(executive.prints[-1]) - 1004.0) < 0.1, executive.prints


@pytest.mark.sim
def test_a_completely_known_motion_is_never_computed_from_a_dummy() -> None:
    executive, robot = run_with_laser("0mm", 0.004, known="completely")
    assert robot.planning.from_dummy == 0 and robot.planning.planned_ahead == 0
    assert abs(float(executive.prints[-1]) - 1004.0) < 0.1, executive.prints


@pytest.mark.sim
def test_a_small_correction_lands_on_the_real_target() -> None:
    executive, robot = run_with_laser("0mm", -0.006)
    assert (robot.planning.from_dummy, robot.planning.corrected) == (1, 1)
    assert abs(float(executive.prints[-1]) - 994.0) < 0.1, executive.prints
