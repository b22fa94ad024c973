"""The headless pendant session: jogging, modes, touch-up, structured edits, execution and read-outs."""

from __future__ import annotations

import math

import numpy as np
import pytest

from orc_rpl.pendant.tree import EditError
from orc_rpl.syntax.parser import parse
from tests.pendant.support import (
    FRAME_PROGRAM, LINE_FRAME, LINE_MOVE_POS0, LINE_MOVE_POS1, LINE_MOVE_POS2, LINE_MOVE_POS3, session_on, tcp_m,
)

# -- jogging -------------------------------------------------------------------------------------


def test_jog_joint_moves_only_that_joint_by_the_amount(tmp_path) -> None:
    session = session_on(tmp_path)
    before = np.array(session.robot.joints_deg())
    session.jogger.jog("joint", "3", "+5deg")
    delta = np.array(session.robot.joints_deg()) - before
    np.testing.assert_allclose(delta, [0, 0, 5, 0, 0, 0], atol=1e-6)


@pytest.mark.parametrize("command, expected_mm", [
    (("world", "x", "+10mm"), (10, 0, 0)),
    (("world", "z", "-2mm"), (0, 0, -2)),
    (("frame", "y", "+1mm", "base_plate"), (-1, 0, 0)),  # base_plate is turned 90 deg: its y is world -x
], ids=["world-x", "world-z", "frame-y"])
def test_jog_cartesian_moves_the_tcp_along_the_axis(tmp_path, command, expected_mm) -> None:
    session = session_on(tmp_path)
    before = tcp_m(session)
    session.jogger.jog(*command[:3], frame=command[3] if len(command) > 3 else None)
    np.testing.assert_allclose((tcp_m(session) - before) * 1000, expected_mm, atol=1e-3)


def test_jog_tool_z_moves_along_the_tool_axis(tmp_path) -> None:
    session = session_on(tmp_path)
    session.editor.goto(LINE_MOVE_POS0)
    session.execution.exec_cursor()  # pos0 points the flange down: tool z is world -z
    before = tcp_m(session)
    session.jogger.jog("tool", "z", "-2mm")
    np.testing.assert_allclose((tcp_m(session) - before) * 1000, (0, 0, 2), atol=1e-3)


def test_jog_keys_step_the_selected_axis_by_the_increment(tmp_path) -> None:
    session = session_on(tmp_path)
    session.jogger.cycle_space()  # joint -> world
    session.jogger.select_axis(2)  # x -> z
    before = tcp_m(session)
    session.jogger.jog_key(+1)
    session.jogger.cycle_increment()  # 1 mm -> 0.1 mm
    session.jogger.jog_key(-1)
    np.testing.assert_allclose((tcp_m(session) - before) * 1000, (0, 0, 0.9), atol=1e-3)


@pytest.mark.parametrize("args, message", [
    (("joint", "9", "+5deg"), "joints 1 to 6"),
    (("world", "q", "+5mm"), "unknown axis"),
    (("world", "x", "+5deg"), "must be a length"),
    (("joint", "2", "fast"), "cannot read the amount"),
    (("frame", "x", "+1mm", "nowhere"), "not a declared FRAME"),
], ids=["joint-number", "axis", "dimension", "amount", "frame"])
def test_bad_jogs_are_refused_with_a_message_and_nothing_moves(tmp_path, args, message) -> None:
    session = session_on(tmp_path)
    before = session.robot.joints()
    with pytest.raises(Exception, match=message):
        session.jogger.jog(*args[:3], frame=args[3] if len(args) > 3 else None)
    assert session.robot.joints() == before


def _peak_tcp_speed(session, text: str) -> float:  # noqa: ANN001
    """Run a typed statement cycle by cycle and return the highest TCP speed (m/s)."""
    session.execution.synchronous = False
    session.execution.execute_text(text)
    last, peak, dt = tcp_m(session), 0.0, session.robot.dt_s
    while session.execution.busy:
        session.execution.pump(1)
        now = tcp_m(session)
        peak, last = max(peak, float(np.linalg.norm(now - last)) / dt), now
    session.execution.synchronous = True
    return peak


def test_manual_mode_caps_program_motions_at_250_mm_per_s(tmp_path) -> None:
    session = session_on(tmp_path)
    assert session.execution.mode == "manual", "a pendant starts in manual mode"
    session.execution.set_mode("auto")
    assert _peak_tcp_speed(session, "MOVE ARM TO pos0") > 0.5, "the auto-mode motion should be fast"
    session.execution.set_mode("manual")
    peak = _peak_tcp_speed(session, "MOVE ARM TO pos3")
    assert peak <= 0.25 * 1.02, f"manual mode TCP speed {peak:.3f} m/s exceeds 250 mm/s (2 % sampling tolerance)"


def test_override_scales_program_motions(tmp_path) -> None:
    session = session_on(tmp_path)
    t0 = session.robot.time_s()
    session.execution.execute_text("MOVE ARM TO pos0")
    full = session.robot.time_s() - t0
    session.execution.execute_text("MOVE ARM TO pos3")
    session.execution.set_override(0.5)
    t0 = session.robot.time_s()
    session.execution.execute_text("MOVE ARM TO pos0")
    assert session.robot.time_s() - t0 > 1.5 * full


# -- touch-up ------------------------------------------------------------------------------------


def test_modpos_keeps_the_original_and_undo_restores_it(tmp_path) -> None:
    session = session_on(tmp_path)
    session.editor.goto(LINE_MOVE_POS2)
    session.execution.exec_cursor()
    session.jogger.jog("world", "z", "+12mm")
    session.modpos("pos2")
    line = next(t for t in session.editor.text.splitlines() if t.startswith("POS pos2"))
    assert line == "POS pos2 = POSE(100mm, 100mm, 62mm, 0, 180deg, 0) IN base_plate"
    listing = session.panels.positions()
    assert "original:  POS pos2 = POSE(100mm, 100mm, 50mm, 0, 180deg, 0) IN base_plate" in listing
    session.editor.undo("pos2")
    assert "POS pos2 = POSE(100mm, 100mm, 50mm, 0, 180deg, 0) IN base_plate" in session.editor.text
    assert "original" not in session.panels.positions()


def test_teach_refuses_a_name_in_use_and_reserved_words(tmp_path) -> None:
    session = session_on(tmp_path)
    with pytest.raises(EditError, match="already declared at line 3 \\(:modpos pos1"):
        session.teach("pos1")
    with pytest.raises(EditError, match="reserved"):
        session.teach("LMOVE")


def test_insert_move_without_a_name_uses_the_first_free_pN(tmp_path) -> None:
    session = session_on(tmp_path)
    session.editor.goto(LINE_MOVE_POS3)
    session.insert_move()
    session.insert_move()
    assert session.editor.text.rstrip().splitlines()[-2:] == ["MOVE ARM TO p1", "MOVE ARM TO p2"]


# -- structured editing ------------------------------------------------------------------------------


def test_select_and_wrap_in_a_frame_block(tmp_path) -> None:
    session = session_on(tmp_path, FRAME_PROGRAM.replace("IN base_plate", ""))
    session.editor.goto(LINE_MOVE_POS3)
    session.editor.select()
    session.editor.goto(LINE_MOVE_POS3)
    session.editor.wrap("base_plate")
    assert "FRAME base_plate\n    MOVE ARM TO pos3\nENDFRAME\n" in session.editor.text
    assert "check error" in session.events.lines[-1]  # pos3 is relative to world: the checker says so at once


def test_delete_shift_replace_and_undo(tmp_path) -> None:
    session = session_on(tmp_path)
    session.editor.goto(LINE_MOVE_POS2)
    session.editor.shift("up")
    assert "    MOVE ARM TO pos2\n    MOVE ARM TO pos1\n" in session.editor.text
    assert session.editor.cursor_line == LINE_MOVE_POS1
    session.editor.replace("MOVE ARM TO pos2 WITH SPEED = 50%")
    assert "    MOVE ARM TO pos2 WITH SPEED = 50%\n" in session.editor.text
    session.editor.delete()
    assert "pos2 WITH" not in session.editor.text
    for _ in range(3):
        session.editor.undo()
    assert session.editor.text == FRAME_PROGRAM


def test_an_edit_that_does_not_parse_leaves_the_program_unchanged(tmp_path) -> None:
    session = session_on(tmp_path)
    session.editor.goto(LINE_MOVE_POS1)
    with pytest.raises(EditError, match="<pendant>:1"):
        session.editor.replace("MOVE ARM TO")
    with pytest.raises(EditError):
        session.editor.insert("ENDFRAME")
    assert session.editor.text == FRAME_PROGRAM


def test_insert_on_a_block_header_goes_inside_and_on_its_end_line_after_it(tmp_path) -> None:
    session = session_on(tmp_path)
    session.editor.goto(LINE_FRAME)
    session.editor.insert("WAIT 1s")
    assert "FRAME base_plate\n    WAIT 1s\n" in session.editor.text
    session.editor.goto(LINE_FRAME + 4, end=True)  # ENDFRAME moved down by one
    session.editor.insert("WAIT 2s")
    assert "ENDFRAME\nWAIT 2s\n" in session.editor.text
    parse(session.editor.text)


# -- execution -------------------------------------------------------------------------------------------


def test_run_step_back_and_stop(tmp_path) -> None:
    session = session_on(tmp_path)
    session.editor.goto(1)
    session.pointer.pp()
    while session.execution.pointer_line != LINE_MOVE_POS1:
        session.execution.step()
    at_pos0 = tcp_m(session)
    session.execution.step()
    assert "back over MOVE; program pointer at line 9" in session.pointer.back()
    np.testing.assert_allclose(tcp_m(session), at_pos0, atol=1e-4)
    assert session.execution.pointer_line == LINE_MOVE_POS1
    assert session.execution.run() == "program finished"
    session.execution.synchronous = False
    session.editor.goto(LINE_MOVE_POS0)
    session.pointer.pp()
    session.execution.run()
    session.execution.pump(30)
    assert session.execution.busy
    session.execution.stop()
    assert not session.execution.busy and session.robot.pending() == 0
    assert session.execution.pointer_line == LINE_MOVE_POS0  # the stopped motion runs again on :run


def test_run_time_errors_are_reported_at_their_line_without_traceback(tmp_path) -> None:
    session = session_on(tmp_path, FRAME_PROGRAM.replace("MOVE ARM TO pos3", "MOVE ARM TO POSE(5, 0, 0, 0, 0, 0)"))
    session.editor.goto(1)
    answer = session.execution.run()
    assert f"cell.rpl:{LINE_MOVE_POS3}:1:" in answer and "Traceback" not in answer


def test_typed_print_and_variables(tmp_path) -> None:
    session = session_on(tmp_path)
    session.execution.execute_text("VAR n = 3")
    assert session.execution.execute_text("PRINT n * 2") == "6\ndone: PRINT n * 2"


def test_pp_makes_a_slow_approach_to_the_start_of_the_statement(tmp_path) -> None:
    session = session_on(tmp_path)
    session.editor.goto(LINE_MOVE_POS3)
    answer = session.pointer.pp()
    assert "approach to the end of line 10's motion at 10% speed" in answer
    assert session.execution.pointer_line == LINE_MOVE_POS3
    session.editor.goto(LINE_MOVE_POS2)
    session.execution.exec_cursor()
    here = tcp_m(session)
    session.editor.goto(LINE_MOVE_POS3)
    session.pointer.pp()
    np.testing.assert_allclose(tcp_m(session), here, atol=1e-4)  # already at the end of pos2's motion


# -- read-outs -------------------------------------------------------------------------------------------


def test_io_can_be_read_and_set(tmp_path) -> None:
    session = session_on(tmp_path)
    session.panels.set_io("DigIn[3]", "1")
    assert "3:1" in session.panels.io().splitlines()[0]
    session.execution.execute_text("DigOut[2] = 1")
    assert session.robot.io.bank("DigOut")[2]
    with pytest.raises(EditError, match="DigIn\\[3\\] or AnalogOut"):
        session.panels.set_io("Dig[3]", "1")


def test_help_covers_every_registered_primitive_from_its_declaration(tmp_path) -> None:
    session = session_on(tmp_path)
    registry = session.registry
    for keyword, spec in registry.motions.items():
        text = session.panels.help(keyword)
        assert spec.doc in text and all(a.name in text for a in spec.attributes), keyword
    for name, spec in {**registry.functions, **registry.install_kinds}.items():
        assert spec.doc in session.panels.help(name), name
    assert "teach NAME" in session.panels.help("teach") and "FRAME name" in session.panels.help("FRAME")


def test_where_shows_the_tcp_in_the_cursor_frame(tmp_path) -> None:
    session = session_on(tmp_path)
    session.editor.goto(LINE_MOVE_POS1)
    session.execution.exec_cursor()
    where = session.panels.where()
    assert "in base_plate: (100.00, -100.00, 50.00) mm, (0.00, 180.00, 0.00) deg" in where  # as declared
    assert "-0.00" not in where
    session.editor.goto(LINE_MOVE_POS3)
    assert "in world:" in session.panels.where()


def test_check_reports_problems_with_their_line(tmp_path) -> None:
    session = session_on(tmp_path)
    assert session.panels.check() == "check: no errors"
    session.editor.goto(LINE_MOVE_POS3)
    session.editor.insert("MOVE ARM TO pos1")
    assert f"cell.rpl:{LINE_MOVE_POS3 + 1}:" in session.panels.check()


def test_snapshot_renders_the_cell_or_explains_why_not(tmp_path) -> None:
    session = session_on(tmp_path)
    with pytest.raises(EditError, match="kinematic backend"):
        session.panels.snapshot(str(tmp_path / "cell.png"))
    assert math.isfinite(session.robot.time_s())


def test_snapshot_writes_a_png_of_the_cell_with_offscreen_gl(tmp_path) -> None:
    import os
    import subprocess
    import sys

    script = ("import sys\nfrom orc_rpl.pendant.session import PendantSession\n"
              "s = PendantSession(sys.argv[1], journal=False)\nprint(s.panels.snapshot(sys.argv[2]))\n")
    (tmp_path / "cell.rpl").write_text("", encoding="utf-8")
    env = {**os.environ, "MUJOCO_GL": "egl"}
    done = subprocess.run([sys.executable, "-c", script, str(tmp_path / "cell.rpl"), str(tmp_path / "cell.png")],
                          capture_output=True, text=True, env=env, timeout=120)
    if done.returncode != 0 or not (tmp_path / "cell.png").exists():
        pytest.skip(f"no offscreen OpenGL here: {(done.stdout + done.stderr).strip().splitlines()[-1:]}")
    assert (tmp_path / "cell.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
