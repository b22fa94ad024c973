"""The pendant with external axes: `:jog axis NAME AMOUNT` moves a track or a positioner alone, and a taught
position carries the axes' values (AXES(POSE(...), ...)), which a program then moves back to."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from orc_rpl.executive.cell_robot import CellRobot
from orc_rpl.pendant.jog import JogError
from orc_rpl.pendant.robot import PendantRobot
from orc_rpl.pendant.session import PendantSession
from orc_rpl.pendant.tree import EditError
from orc_rpl.plant.world_scene import cell_from_world
from orc_rpl.world import load_world
from tests.conftest import ROOT

PROGRAM = """\
TOOL torch = POSE(0, 0, 200mm, 0, 0, 0)
FRAME plate = POSE(0, 0, 0, 0, 0, 0) IN turn
"""


def _session(tmp_path: Path) -> PendantSession:
    world = load_world(ROOT / "worlds" / "positioner_cell.yaml")
    cell = CellRobot.virtual(cell=cell_from_world(world), plant="ideal")
    cell.attach_world(world)
    path = tmp_path / "cell.rpl"
    path.write_text(PROGRAM, encoding="utf-8")
    return PendantSession(path, robot=PendantRobot(cell))


def test_jogging_an_axis_moves_it_alone_and_teaching_records_its_value(tmp_path: Path) -> None:
    session = _session(tmp_path)
    robot = session.robot.cell
    joints = robot.joints()
    session.jogger.jog("axis", "turn", "+30deg")
    session.jogger.jog("axis", "track", "+100mm")
    for _ in range(100):
        session.robot.tick()
    values = robot.axes.values()
    assert values["turn"] == pytest.approx(math.radians(30), abs=1e-3) and values["track"] == pytest.approx(0.1, abs=1e-4)
    assert max(abs(a - b) for a, b in zip(joints, robot.joints())) < 1e-3  # the arm stood still
    session.execution.set_tool("torch")
    session.teach("p1")
    text = session.editor.text
    assert re.search(r"POS p1 = AXES\(POSE\(921.349mm, 0, 774.413mm, 0, 180deg, 0\), track = 100mm, tilt = 0, turn = 30deg\)",
                     text), text  # the TCP in the cell's world: the track carried the robot 100 mm along x
    with pytest.raises(JogError, match="axis turn: .* is outside its range"):
        session.jogger.jog("axis", "turn", "+400deg")
    with pytest.raises(JogError, match="no external axis 'belt'"):
        session.jogger.jog("axis", "belt", "+1mm")


def test_a_taught_position_with_axis_values_is_reached_again(tmp_path: Path) -> None:
    session = _session(tmp_path)
    session.execution.set_tool("torch")
    session.jogger.jog("axis", "track", "+150mm")
    session.teach("p1")
    session.jogger.jog("axis", "track", "-150mm")
    session.jogger.jog("world", "z", "-20mm")
    robot = session.robot.cell
    assert robot.axes.values()["track"] == pytest.approx(0.0, abs=1e-4)
    session.execution.execute_text("MOVE torch TO p1")
    assert robot.axes.values()["track"] == pytest.approx(0.15, abs=1e-4)


def test_the_pendant_checks_know_the_cells_moving_frames(tmp_path: Path) -> None:
    session = _session(tmp_path)
    assert session.editor.check_diagnostics() == []  # `IN turn` names the positioner's table
    session.execution.execute_text("FRAME q = POSE(0, 0, 0, 0, 0, 0) IN turn")  # checked before it runs
    with pytest.raises(EditError, match="unknown frame 'belt'"):
        session.execution.execute_text("FRAME r = POSE(0, 0, 0, 0, 0, 0) IN belt")
