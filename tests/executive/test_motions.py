"""Motion statements on the recording robot: requests, frames, blending look-ahead, UNTIL, function parameters, IO scripts."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from orc_rpl.application.runtime import FINE
from orc_rpl.executive.recording_robot import RecordingRobot
from orc_rpl.executive.sim_io import load_script
from orc_rpl.errors import UsageError
from tests.executive.support import execute

POSITIONS = """
TOOL gripper = POSE(0, 0, 100mm, 0, 0, 0)
POS a = POSE(900mm, -200mm, 700mm, 0, 180deg, 0)
POS b = POSE(900mm, 200mm, 700mm, 0, 180deg, 0)
POS c = POSE(1000mm, 0, 600mm, 0, 180deg, 0)
"""


def run(text: str, robot: RecordingRobot | None = None):  # type: ignore[no-untyped-def]
    executive = execute(POSITIONS + text, robot)
    assert executive.status == "finished", executive.report()
    return executive


def test_standard_attributes_become_the_request() -> None:
    robot = run("LMOVE gripper TO a WITH V = 0.5mps WITH ACCEL = 50% WITH TIME = 2s WITH LOAD = 3kg").robot
    request = robot.recorded[0].request
    assert (request.kind, request.speed_m_s, request.accel_fraction, request.time_s, request.load_kg) == ("linear", 0.5, 0.5, 2.0, 3.0)
    assert request.tool.z == pytest.approx(0.1) and request.zone_m == 0.0


def test_speed_as_fraction_and_override() -> None:
    executive = execute(POSITIONS + "MOVE gripper TO a WITH SPEED = 50%", speed_override=0.5)
    request = executive.robot.recorded[0].request
    assert request.kind == "joint" and request.speed_m_s is None and request.speed_fraction == pytest.approx(0.25)


def test_zone_motion_is_given_while_the_previous_one_runs() -> None:
    robot = run("""
        LMOVE gripper TO a
        LMOVE gripper TO b WITH ZONE = 20mm
        LMOVE gripper TO c WITH ZONE = 20mm
        LMOVE gripper TO a
        """).robot
    assert [r.pending_before for r in robot.recorded] == [0, 0, 1, 1]
    assert [r.request.zone_m for r in robot.recorded] == [0.0, 0.02, 0.02, 0.0]


def test_look_ahead_is_one_motion() -> None:
    robot = run("FOR i FROM 1 TO 4 DO\n    LMOVE gripper TO a WITH ZONE = 5mm\n    LMOVE gripper TO b WITH ZONE = 5mm\nENDFOR").robot
    assert max(r.pending_before for r in robot.recorded) == 1


def test_an_output_waits_for_the_robot_to_arrive() -> None:
    robot = run("LMOVE gripper TO a WITH ZONE = 20mm\nDigOut[1] = 1\nLMOVE gripper TO b WITH ZONE = 20mm").robot
    assert [r.pending_before for r in robot.recorded] == [0, 0]


def test_frame_block_targets_are_moved_to_world_and_here_is_relative() -> None:
    executive = run("""
        FRAME table = POSE(1000mm, 0, 500mm, 0, 0, 90deg)
        POS p = POSE(0, 100mm, 200mm, 0, 180deg, 0) IN table
        FRAME table
            LMOVE ARM TO p
            PRINT ROUND(HERE.y / 1mm, 6), ROUND(HERE.z / 1mm, 6)
        ENDFRAME
        PRINT ROUND(HERE.x / 1mm, 6), ROUND(HERE.y / 1mm, 6), ROUND(HERE.z / 1mm, 6)
        """)
    target = executive.robot.recorded[0].request.target
    assert (target.x, target.y, target.z) == pytest.approx((1.0, -0.2, 0.6))  # (0, 0.1, 0.2) turned 90 deg about x
    assert executive.prints == ["100 200", "1000 -200 600"]


def test_offs_keeps_the_frame_of_its_pose() -> None:
    executive = run("""
        FRAME table = POSE(1000mm, 0, 500mm, 0, 0, 0)
        POS p = POSE(0, 0, 200mm, 0, 180deg, 0) IN table
        FRAME table
            MOVE ARM TO OFFS(p, 0, 0, 100mm)
        ENDFRAME
        """)
    assert executive.robot.recorded[0].request.target.z == pytest.approx(0.8)


def test_until_stops_the_motion_on_its_path() -> None:
    robot = RecordingRobot()
    robot.io.add_process(lambda io, t: io.dig_in.__setitem__(2, t >= 0.2))
    executive = run("""
        LMOVE ARM TO a
        LMOVE ARM TO b WITH SPEED = 0.4mps UNTIL DigIn[2] = 1
        PRINT ROUND(HERE.y / 1mm, 0)
        """, robot)
    y_mm = float(executive.prints[0])
    assert -200 < y_mm < 200  # stopped between a and b, not at b


def test_until_never_true_raises_notfound() -> None:
    executive = execute(POSITIONS + "TRY\n    LMOVE ARM TO a UNTIL DigIn[2] = 1\nON NotFound : PRINT \"no part\"\nENDTRY")
    assert executive.prints == ["no part"]


def test_func_attribute_is_a_function_of_the_path_coordinate() -> None:
    executive = run("""
        FUNC slow_end(s)
            RETURN 0.5mps - 0.4mps * s
        ENDFUNC
        LMOVE gripper TO a WITH SPEED = slow_end
        """)
    speed = executive.robot.recorded[0].request.speed_m_s
    assert callable(speed) and speed(0.0) == pytest.approx(0.5) and speed(1.0) == pytest.approx(0.1)


def test_along_path_and_via_points() -> None:
    robot = run("""
        PATH edge = [a, c, b]
        LMOVE gripper ALONG edge
        MOVE gripper TO a VIA c, b
        CMOVE gripper VIA c TO b
        """).robot
    along, via, circle = (r.request for r in robot.recorded)
    assert along.target.y == pytest.approx(0.2) and len(along.via) == 2
    assert len(via.via) == 2 and circle.kind == "circular" and circle.via[0].x == pytest.approx(1.0)


def test_joints_target_and_fine_zone() -> None:
    robot = run("MOVE ARM TO JOINTS(0, -30deg, 30deg, 0, 45deg, 0) WITH ZONE = FINE").robot
    request = robot.recorded[0].request
    assert request.target.values[1] == pytest.approx(-math.pi / 6) and request.zone_m == 0.0 and FINE is not None


def test_io_script_events(tmp_path: Path) -> None:
    script = tmp_path / "cell.sim.yaml"
    script.write_text("events:\n"
                      "  - {at: 0.2s, set: 'DigIn[1]', value: 1}\n"
                      "  - {when: 'DigOut[2] = 1', after: 0.1s, set: 'DigIn[3]'}\n"
                      "  - {when: 'TCP.z < 650mm', set: 'DigIn[4]'}\n")
    robot = RecordingRobot()
    load_script(script, robot.io, lambda: robot.tcp_pose(None))
    executive = execute(POSITIONS + """
        WAIT UNTIL DigIn[1] = 1 TIMEOUT 1s
        PRINT "part", ROUND(HERE.z / 1mm, 0) > 0
        DigOut[2] = 1
        WAIT UNTIL DigIn[3] = 1 TIMEOUT 1s
        LMOVE ARM TO c UNTIL DigIn[4] = 1
        PRINT "found"
        """, robot)
    assert executive.status == "finished", executive.report()
    assert executive.prints == ["part TRUE", "found"]
    assert 0.2 <= robot.time_s() < 2.0


def test_io_script_mistakes_name_the_event(tmp_path: Path) -> None:
    script = tmp_path / "bad.sim.yaml"
    script.write_text("events:\n  - {at: 1s, set: 'DigIn[99]'}\n")
    with pytest.raises(UsageError, match="event 1"):
        load_script(script, RecordingRobot().io, lambda: None)  # type: ignore[arg-type,return-value]


def test_a_func_as_target_is_a_motion_in_function_space() -> None:
    executive = run("""
        FRAME f = POSE(900mm, 0, 600mm, 0, 0, 0)
        POS start = POSE(0, 0, 100mm, 0, 180deg, 0) IN f
        FUNC arc(s)
            RETURN OFFS(start, 100mm * SIN(s * 180deg), 300mm * s, 0)
        ENDFUNC
        FRAME f
            MOVE ARM TO start
            LMOVE ARM TO arc
            PRINT ROUND(HERE.y / 1mm, 3)
        ENDFRAME
        """)
    request = executive.robot.recorded[-1].request
    assert request.kind == "function" and request.target.fn(0.5).x == pytest.approx(1.0)  # world x at the arc's top
    assert executive.prints == ["300"]


def test_a_func_target_in_the_wrong_frame_moves_nothing() -> None:
    executive = execute(POSITIONS + """
        FUNC line(s)
            RETURN OFFS(a, 0, 100mm * s, 0)
        ENDFUNC
        FRAME f = POSE(900mm, 0, 600mm, 0, 0, 0)
        FRAME f
            LMOVE ARM TO line
        ENDFRAME
        """)
    assert executive.status == "failed" and "relative to world, but this motion is inside FRAME f" in executive.error.message
    assert executive.robot.recorded == []
