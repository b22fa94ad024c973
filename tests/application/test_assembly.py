"""Assembly (thesis 2.4, 4.5) end to end: ROBOT.Thermal read from programs, the demo's two branches, CALIBRATE and TUNING."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

from orc_rpl.executive.cell_robot import CellRobot
from orc_rpl.executive.executive import Executive
from orc_rpl.executive.recording_robot import RecordingRobot
from orc_rpl.syntax.parser import parse

ROOT = Path(__file__).resolve().parents[2]


def run(source: str, robot: object) -> Executive:
    source = textwrap.dedent(source)
    executive = Executive(parse(source, "assembly.rpl"), robot, path="assembly.rpl", source=source,  # type: ignore[arg-type]
                          output=lambda line: None)
    executive.run()
    return executive


def run_file(name: str) -> Executive:
    path = ROOT / "programs" / "online" / name
    return run(path.read_text(), CellRobot.virtual())


@pytest.mark.sim
def test_robot_thermal_is_a_software_sensor_that_rises_while_the_robot_works() -> None:
    ex = run("""
        TOOL gripper = POSE(0, 0, 120mm, 0, 0, 0)
        POS a = POSE(1350mm, -300mm, 450mm, 0, 180deg, 0)
        POS b = POSE(1350mm, 300mm, 450mm, 0, 180deg, 0)
        PRINT ROBOT.Thermal[2]
        MOVE gripper TO a
        MOVE gripper TO b
        PRINT ROBOT.Thermal[2] > 0.05, ROBOT.Thermal[2] < 1, LEN(ROBOT.Thermal), ROBOT.Torque[2] < 0Nm, ROBOT.PosError < 1mm
        """, CellRobot.virtual())
    assert ex.status == "finished", ex.report()
    assert ex.prints == ["0", "TRUE TRUE 6 TRUE TRUE"]


def test_the_recording_robot_has_cold_motors() -> None:
    ex = run("PRINT ROBOT.Thermal\n", RecordingRobot())
    assert ex.status == "finished", ex.report()
    assert ex.prints == ["[0, 0, 0, 0, 0, 0]"]


@pytest.mark.sim
def test_demo_thermal_takes_both_branches_and_finishes() -> None:
    ex = run_file("demo_thermal.rpl")
    assert ex.status == "finished", ex.report()
    assert any("energy saving" in line for line in ex.prints) and any("fast" in line for line in ex.prints)
    assert ex.prints[-1] == "15 fast cycles, 9 energy-saving cycles", "deterministic: the same cycles every run"
