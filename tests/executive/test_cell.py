"""End to end on the simulated cell (MuJoCo): motions, HERE, UNTIL, blending, frames, errors, speed override."""

from __future__ import annotations

import textwrap

import numpy as np
import pytest

from orc_rpl.executive.cell_robot import CellRobot
from orc_rpl.executive.executive import Executive
from orc_rpl.executive.machine import Options
from orc_rpl.syntax.parser import parse

pytestmark = pytest.mark.sim

SETUP = """
TOOL gripper = POSE(0, 0, 150mm, 0, 0, 0)
FRAME table = POSE(900mm, 0, 500mm, 0, 0, 0)
POS a = POSE(900mm, -200mm, 700mm, 0, 180deg, 0)
POS b = POSE(900mm, 200mm, 700mm, 0, 180deg, 0)
POS c = POSE(1050mm, 200mm, 600mm, 0, 180deg, 0)
POS t = POSE(100mm, 0, 150mm, 0, 180deg, 0) IN table
"""


def run(text: str, robot: CellRobot | None = None, **options: object) -> Executive:
    source = SETUP + textwrap.dedent(text)
    executive = Executive(parse(source, "cell.rpl"), robot or CellRobot.virtual(), path="cell.rpl", source=source,
                          output=lambda line: None, options=Options(**options) if options else None)  # type: ignore[arg-type]
    executive.run()
    return executive


def test_motions_reach_their_targets_and_here_reads_them_in_the_frame() -> None:
    ex = run("""
        MOVE gripper TO a
        PRINT ROUND(HERE.x / 1mm, 0), ROUND(HERE.y / 1mm, 0), ROUND(HERE.z / 1mm, 0)
        FRAME table
            LMOVE gripper TO t
            PRINT ROUND(HERE.x / 1mm, 0), ROUND(HERE.z / 1mm, 0)
        ENDFRAME
        CMOVE gripper VIA b TO c
        """)
    assert ex.status == "finished", ex.report()
    assert ex.prints == ["900 -200 700", "100 150"]
    tcp = ex.robot.tcp_pose(ex.machine.last_tool)
    assert np.allclose((tcp.x, tcp.y, tcp.z), (1.05, 0.2, 0.6), atol=5e-4), "a FINE motion ends within 0.5 mm"


def test_until_stops_the_robot_on_its_path() -> None:
    robot = CellRobot.virtual()
    robot.io.add_process(lambda io, time_s: io.dig_in.__setitem__(1, robot.tcp_pose(None).y > 0.0))
    ex = run("""
        MOVE gripper TO a
        LMOVE gripper TO b WITH SPEED = 0.3mps UNTIL DigIn[1] = 1
        PRINT HERE.y > 0mm, HERE.y < 60mm
        """, robot)
    assert ex.status == "finished", ex.report()
    assert ex.prints == ["TRUE TRUE"], "stopped just after the input rose, decelerating on the line"
    assert np.max(np.abs(robot.layer.current_q() - robot.layer.reference_q())) < 1e-3


def test_zone_motions_blend_and_save_time() -> None:
    path = "MOVE gripper TO a\nLMOVE gripper TO b WITH ZONE = {z}\nLMOVE gripper TO c WITH ZONE = {z}\nLMOVE gripper TO a\n"
    fine, blended = run(path.format(z="FINE")), run(path.format(z="50mm"))
    assert fine.status == blended.status == "finished"
    assert blended.robot.time_s() < fine.robot.time_s() - 0.1, (blended.robot.time_s(), fine.robot.time_s())


def test_frame_mismatch_is_an_error_before_anything_moves() -> None:
    robot = CellRobot.virtual()
    q0 = robot.layer.current_q()
    ex = run("FRAME table\n    MOVE gripper TO a\nENDFRAME\n", robot)
    assert ex.status == "failed" and (ex.error.span.line, ex.error.span.column) == (9, 5)
    assert "relative to world, but this motion is inside FRAME table" in ex.error.message
    assert robot.time_s() == 0.0 and np.array_equal(robot.layer.current_q(), q0)


def test_error_during_a_blended_motion_stops_the_robot_on_its_path() -> None:
    ex = run("MOVE gripper TO a\nLMOVE gripper TO b WITH ZONE = 20mm\nPRINT 1 / 0\n")
    assert ex.status == "failed" and ex.error.span.line == 10
    robot = ex.robot
    assert robot.pending() == 0 and float(np.max(np.abs(robot.layer.backend.qd()))) < 0.05
    assert robot.tcp_pose(None).y < 0.15, "stopped before reaching b"


def test_speed_override_slows_the_program_down() -> None:
    program = "MOVE gripper TO a\nLMOVE gripper TO b WITH SPEED = 0.5mps\n"
    full, half = run(program), run(program, speed_override=0.5)
    assert half.robot.time_s() > 1.6 * full.robot.time_s(), "speeds halve and accelerations quarter"


def test_func_speed_is_a_function_of_the_path_coordinate() -> None:
    ex = run("""
        FUNC ramp(s)
            RETURN 0.1mps + 0.4mps * s
        ENDFUNC
        MOVE gripper TO a
        LMOVE gripper TO b WITH SPEED = ramp
        PRINT LEN(ROBOT.Joints)
        """, CellRobot.virtual(plant="ideal"))  # the timing bound below is the ideal plant's settling
    assert ex.status == "finished", ex.report()
    assert ex.prints == ["6"]
    # 0.4 m at 0.1..0.5 m/s takes 0.4 / 0.5 * ln(5) = 1.29 s plus the move to a and the settling
    assert 1.4 < ex.robot.time_s() < 3.0
