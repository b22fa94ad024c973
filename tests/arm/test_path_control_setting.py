"""PATHCONTROL per motion and ROBOT.PathControl for the program: which motions run under the path velocity controller."""

from __future__ import annotations

import textwrap

import pytest

from orc_rpl.application.standard_behaviour import runtime_registry
from orc_rpl.checking.checker import check_program
from orc_rpl.executive.cell_robot import CellRobot
from orc_rpl.executive.executive import Executive
from orc_rpl.syntax.parser import parse

SETUP = """\
TOOL gripper = TRANSL(0, 0, 100mm)
POS a = POSE(900mm, -200mm, 700mm, 0, 180deg, 0)
POS b = POSE(900mm, 200mm, 700mm, 0, 180deg, 0)
"""


def controlled_motions(body: str, plant: str = "realistic") -> tuple[list[bool], list[str]]:
    """Per motion (in order): was it run under the path velocity controller; and the program's prints."""
    source = SETUP + textwrap.dedent(body)
    robot = CellRobot.virtual(plant=plant)
    layer, seen = robot.layer, {}
    tick = layer.tick

    def watched() -> None:
        tick()
        if layer._active is not None and layer._traj is not None:
            seen.setdefault(layer._active.id, layer.pvc is not None)

    layer.tick = watched  # type: ignore[method-assign]
    prints: list[str] = []
    executive = Executive(parse(source, "pc.rpl"), robot, path="pc.rpl", source=source, output=prints.append)
    executive.run()
    assert executive.status == "finished", executive.report()
    return [seen[k] for k in sorted(seen)], prints


@pytest.mark.sim
def test_on_by_default_on_the_realistic_plant_off_per_motion_and_for_the_program() -> None:
    used, prints = controlled_motions("""
        PRINT ROBOT.PathControl
        MOVE gripper TO a
        LMOVE gripper TO b WITH PATHCONTROL = FALSE
        ROBOT.PathControl = FALSE
        LMOVE gripper TO a
        LMOVE gripper TO b WITH PATHCONTROL = TRUE
        PRINT ROBOT.PathControl
    """)
    assert used == [True, False, False, True]
    assert prints == ["TRUE", "FALSE"]


@pytest.mark.sim
def test_off_by_default_on_the_ideal_plant() -> None:
    used, prints = controlled_motions("PRINT ROBOT.PathControl\nMOVE gripper TO a\n", plant="ideal")
    assert used == [False] and prints == ["FALSE"]


def test_a_value_that_is_not_true_or_false_is_a_check_error() -> None:
    source = SETUP + "MOVE gripper TO a WITH PATHCONTROL = 3\n"
    diagnostics = check_program(parse(source, "pc.rpl"), "pc.rpl", runtime_registry())
    assert [(d.location.line, "PATHCONTROL" in d.message) for d in diagnostics] == [(4, True)]
