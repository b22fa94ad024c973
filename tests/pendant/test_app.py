"""The terminal application driven with prompt-toolkit's pipe input and a dummy output, keys as a person presses them."""

from __future__ import annotations

import asyncio

import numpy as np
from prompt_toolkit.input import create_pipe_input
from prompt_toolkit.output import DummyOutput

from orc_rpl.pendant.app import PendantApp, open_blocks
from orc_rpl.pendant.keys import FUNCTION_KEYS, MODES
from orc_rpl.pendant import views
from tests.pendant.support import LINE_MOVE_POS0, LINE_MOVE_POS1, session_on, tcp_m

F = {1: "\x1bOP", 2: "\x1bOQ", 3: "\x1bOR", 4: "\x1bOS", 5: "\x1b[15~", 6: "\x1b[17~", 7: "\x1b[18~", 8: "\x1b[19~"}
UP, DOWN, RIGHT, LEFT = "\x1b[A", "\x1b[B", "\x1b[C", "\x1b[D"


def drive(session, *keys: str) -> PendantApp:  # noqa: ANN001
    """Start the application, type `keys` one after the other, then leave with :quit!."""

    async def main() -> PendantApp:
        with create_pipe_input() as pipe:
            app = PendantApp(session, input=pipe, output=DummyOutput(), realtime=False)
            task = asyncio.ensure_future(app.run_async())
            for key in keys:
                pipe.send_text(key)
                await asyncio.sleep(0.005)
            pipe.send_text(":quit!\r")
            assert await asyncio.wait_for(task, 20) == 0
            return app

    return asyncio.run(main())


def test_function_keys_change_meaning_with_the_mode(tmp_path) -> None:
    app = drive(session_on(tmp_path), F[8])
    assert app.mode == "edit"
    bar = "".join(text for _, text in views.function_bar([label for label, _ in FUNCTION_KEYS["run"]], "run"))
    assert "F2run" in bar.replace(" ", "") and "F6pp" in bar.replace(" ", "")
    assert drive(session_on(tmp_path), F[8], F[8], F[8]).mode == MODES[0]


def test_jog_keys_move_the_selected_joint_by_the_increment(tmp_path) -> None:
    session = session_on(tmp_path)
    before = np.array(session.robot.joints_deg())
    drive(session, RIGHT, DOWN, LEFT, LEFT, F[3], RIGHT)
    np.testing.assert_allclose(np.array(session.robot.joints_deg()) - before, [1, -1.9, 0, 0, 0, 0], atol=1e-6)


def test_teach_with_f4_and_insert_move_with_f5_inside_the_frame_block(tmp_path) -> None:
    session = session_on(tmp_path)
    drive(session, f":goto {LINE_MOVE_POS1}\r", ":exec\r", ":jog world z +5mm\r", F[4], "corner\r", F[5])
    assert "POS corner = POSE(100mm, -100mm, 55mm, " in session.editor.text
    assert "    MOVE ARM TO pos1\n    MOVE ARM TO p1\n" in session.editor.text


def test_arrows_move_the_cursor_in_edit_mode_and_run_mode_keys_step(tmp_path) -> None:
    session = session_on(tmp_path)
    drive(session, F[8], f":goto {LINE_MOVE_POS0}\r", DOWN, DOWN, F[8], F[6], F[4])
    assert session.execution.pointer_line == LINE_MOVE_POS1 + 1  # F6 set the pointer at the cursor, F4 stepped over it
    expected = np.array([0.9 + 0.1, 0.1, 0.55])  # pos1 in base_plate (turned 90 deg about z)
    np.testing.assert_allclose(tcp_m(session), expected, atol=1e-4)


def test_a_block_typed_over_several_lines_runs_when_it_is_closed(tmp_path) -> None:
    session = session_on(tmp_path)
    drive(session, f":goto {LINE_MOVE_POS1}\r", ":exec\r", "FRAME base_plate\r", "PRINT ROUND(HERE.z / 1mm)\r", "ENDFRAME\r")
    assert session.execution.printed[-1] == "50"  # HERE inside the typed block is relative to base_plate
    assert open_blocks("FRAME a\n  IF x THEN\n  ENDIF") == 1 and open_blocks("WHILE x DO\nENDWHILE") == 0


def test_edit_in_place_replaces_the_statement(tmp_path) -> None:
    session = session_on(tmp_path)
    drive(session, f":goto {LINE_MOVE_POS1}\r", ":edit\r", " WITH SPEED = 50%\r")
    assert "    MOVE ARM TO pos1 WITH SPEED = 50%\n" in session.editor.text


def test_quit_with_unsaved_edits_asks_to_save_first(tmp_path) -> None:
    session = session_on(tmp_path)
    app = drive(session, ":teach p7\r", ":quit\r")
    assert "POS p7" in session.editor.text
    assert app.message == "bye"  # :quit! after the refusal


def test_the_screen_renders_listing_state_and_messages(tmp_path) -> None:
    session = session_on(tmp_path)
    session.editor.goto(LINE_MOVE_POS1)
    text = "".join(t for _, t in views.listing(session, 30))
    assert f"{LINE_MOVE_POS1:4}     MOVE ARM TO pos1" in text
    state = "".join(t for _, t in views.state(session))
    assert "TCP of ARM in base_plate" in state and "override" in state


def test_tab_completes_a_command_and_a_position_name(tmp_path) -> None:
    session = session_on(tmp_path)
    drive(session, f":goto {LINE_MOVE_POS1}\r", ":exec\r", ":jog world z +1mm\r", ":mo\t", "\t", "\t", "\r", "pos2\r")
    # Tab opens the menu (mode, modpos), Tab Tab chooses modpos, Enter takes it; then the name and Enter
    assert "POS pos2 = POSE(100mm, -100mm, 51mm, " in session.editor.text
