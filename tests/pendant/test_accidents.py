"""The two FRAME accidents of thesis section 7.3 cannot happen on this pendant."""

from __future__ import annotations

import numpy as np
import pytest

from orc_rpl.world.pose import Pose
from tests.pendant.support import (
    LINE_ENDFRAME, LINE_FRAME, LINE_MOVE_POS0, LINE_MOVE_POS1, LINE_MOVE_POS3, session_on, tcp_m, world_of,
)

BASE_PLATE = Pose(0.9, 0.0, 0.5, np.pi / 2, 0.0, 0.0)
POS1 = Pose(0.1, -0.1, 0.05, 0.0, np.pi, 0.0)
#: Where pos1 is when its frame is honoured, and where it would be if the block were ignored (world).
POS1_WORLD = world_of(BASE_PLATE, POS1)
POS1_READ_IN_WORLD = np.array([0.1, -0.1, 0.05])


def _start_fresh(session) -> None:  # noqa: ANN001
    """Nothing run yet: the robot at home, the program pointer at the top."""


def _start_after_program(session) -> None:  # noqa: ANN001
    session.execution.run()  # the pointer at the end, the robot at pos3 (outside the block)


def _start_after_jogging(session) -> None:  # noqa: ANN001
    session.jogger.jog("world", "y", "+150mm")
    session.jogger.jog("joint", "1", "-20deg")


def _start_pointer_outside(session) -> None:  # noqa: ANN001
    session.editor.goto(LINE_MOVE_POS3)
    session.pointer.pp()


STARTS = {"fresh": _start_fresh, "after-run": _start_after_program, "after-jogging": _start_after_jogging,
          "pointer-after-the-block": _start_pointer_outside}


@pytest.mark.parametrize("start", list(STARTS), ids=list(STARTS))
def test_exec_of_a_move_inside_a_frame_block_uses_the_block_frame_from_any_start(tmp_path, start) -> None:
    """Accident 1: "execute current instruction" on MOVE ARM TO pos1 must go to pos1 in base_plate."""
    session = session_on(tmp_path)
    STARTS[start](session)
    session.editor.goto(LINE_MOVE_POS1)
    answer = session.execution.exec_cursor()
    assert "FRAME base_plate" in answer, answer
    np.testing.assert_allclose(tcp_m(session), POS1_WORLD, atol=1e-4,
                               err_msg="the move was not executed relative to its FRAME block")
    assert np.linalg.norm(tcp_m(session) - POS1_READ_IN_WORLD) > 0.5


def test_pp_into_a_frame_block_then_step_moves_in_the_block_frame(tmp_path) -> None:
    session = session_on(tmp_path)
    session.editor.goto(LINE_MOVE_POS1)
    session.pointer.pp()
    assert session.execution.pointer_line == LINE_MOVE_POS1
    session.execution.step()
    np.testing.assert_allclose(tcp_m(session), POS1_WORLD, atol=1e-4)


def test_a_statement_typed_with_the_cursor_in_a_block_runs_in_its_frame(tmp_path) -> None:
    session = session_on(tmp_path)
    session.editor.goto(LINE_MOVE_POS1)
    session.execution.execute_text("MOVE ARM TO pos1")
    np.testing.assert_allclose(tcp_m(session), POS1_WORLD, atol=1e-4)


def _taught(session, name: str) -> tuple[Pose, str]:  # noqa: ANN001
    declaration = next(line for line in session.editor.text.splitlines() if line.startswith(f"POS {name} ="))
    value = session.execution.executive().machine.globals[name]
    return value, declaration


def test_a_position_taught_inside_a_block_is_stored_relative_to_its_frame(tmp_path) -> None:
    """Accident 2: a position taught with the cursor in the block must be relative to base_plate."""
    session = session_on(tmp_path)
    session.execution.run()  # the robot ends at pos3, the "current" frame of an ARLA-style system would be world
    session.jogger.jog("world", "z", "-200mm")
    here_world = tcp_m(session)
    session.editor.goto(LINE_MOVE_POS1)
    session.insert_move("pos1b")
    value, declaration = _taught(session, "pos1b")
    assert declaration.endswith("IN base_plate"), declaration
    assert value.frame == "base_plate"
    np.testing.assert_allclose(world_of(BASE_PLATE, value), here_world, atol=1e-5,
                               err_msg="the taught numbers are not the current pose relative to base_plate")
    lines = session.editor.text.splitlines()
    assert lines[lines.index("    MOVE ARM TO pos1") + 1] == "    MOVE ARM TO pos1b"  # inside the block, after pos1


def test_running_the_program_from_the_start_reaches_the_position_taught_in_the_block(tmp_path) -> None:
    session = session_on(tmp_path)
    session.editor.goto(LINE_MOVE_POS1)
    session.execution.exec_cursor()
    session.jogger.jog("world", "x", "+30mm")
    session.jogger.jog("world", "z", "+40mm")
    taught_world = tcp_m(session)
    session.insert_move("pos1b")
    session.jogger.jog("joint", "1", "+40deg")  # move away, then run the whole program from the top
    session.editor.goto(1)
    session.pointer.pp()
    line = session.editor.text.splitlines().index("    MOVE ARM TO pos1b") + 1
    while session.execution.pointer_line != line:
        session.execution.step()
    session.execution.step()
    np.testing.assert_allclose(tcp_m(session), taught_world, atol=1e-4)


def test_a_taught_position_moves_with_its_frame_when_the_fixture_is_relocated(tmp_path) -> None:
    session = session_on(tmp_path)
    session.editor.goto(LINE_MOVE_POS1)
    session.execution.exec_cursor()
    session.insert_move("pos1b")
    session.editor.goto(1)
    session.editor.replace("FRAME base_plate = POSE(950mm, 20mm, 500mm, 90deg, 0, 0)")
    session.editor.goto(session.editor.text.splitlines().index("    MOVE ARM TO pos1b") + 1)
    session.execution.exec_cursor()
    np.testing.assert_allclose(tcp_m(session), POS1_WORLD + [0.05, 0.02, 0.0], atol=1e-4)


@pytest.mark.parametrize("line, frame", [(LINE_MOVE_POS0, "world"), (LINE_FRAME, "base_plate"),
                                         (LINE_MOVE_POS1, "base_plate"), (LINE_ENDFRAME, "world"),
                                         (LINE_MOVE_POS3, "world")],
                         ids=["before-block", "block-header", "inside", "endframe", "after-block"])
def test_teach_takes_the_frame_of_the_block_at_the_cursor(tmp_path, line, frame) -> None:
    session = session_on(tmp_path)
    session.editor.goto(line, end=(line == LINE_ENDFRAME))
    session.teach("taught")
    _, declaration = _taught(session, "taught")
    assert declaration.endswith(" IN base_plate") == (frame == "base_plate"), declaration
