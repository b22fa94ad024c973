"""The autosave journal: a pendant killed at any moment loses no taught position or edit."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

from orc_rpl.pendant.journal import Journal, journal_path, read_journal
from tests.pendant.support import FRAME_PROGRAM, LINE_MOVE_POS1, session_on

ROOT = Path(__file__).resolve().parents[2]

#: A pendant process that teaches, inserts and edits, then is killed with SIGKILL right after the last edit.
KILLED = textwrap.dedent("""\
    import os, signal, sys
    from orc_rpl.pendant.robot import PendantRobot
    from orc_rpl.pendant.session import PendantSession
    session = PendantSession(sys.argv[1], robot=PendantRobot.virtual(backend="kinematic"))
    session.editor.goto(%d)
    session.jogger.jog("world", "z", "+25mm")
    session.insert_move("pos1b")
    session.jogger.jog("world", "x", "+10mm")
    session.teach("pos1c")
    os.kill(os.getpid(), signal.SIGKILL)
    """) % LINE_MOVE_POS1


def test_sigkill_right_after_teaching_loses_nothing(tmp_path) -> None:
    program = tmp_path / "cell.rpl"
    program.write_text(FRAME_PROGRAM, encoding="utf-8")
    done = subprocess.run([sys.executable, "-c", KILLED, str(program)], cwd=ROOT, capture_output=True, timeout=60)
    assert done.returncode == -signal.SIGKILL, done.stderr.decode()
    assert program.read_text(encoding="utf-8") == FRAME_PROGRAM  # nothing was saved
    session = session_on(tmp_path, FRAME_PROGRAM)
    assert session.editor.pending_recovery() == "2 unsaved edits (last: insert move pos1b, teach pos1c)"
    session.editor.recover()
    assert "POS pos1b = POSE(" in session.editor.text and "POS pos1c = POSE(" in session.editor.text
    assert "    MOVE ARM TO pos1b\n" in session.editor.text
    values = session.execution.executive().machine.globals
    assert values["pos1b"].frame == values["pos1c"].frame == "base_plate"
    session.editor.save()
    assert not journal_path(program).exists() and program.read_text(encoding="utf-8") == session.editor.text


def test_a_second_kill_after_recovering_still_loses_nothing(tmp_path) -> None:
    session = session_on(tmp_path)
    session.teach("first")
    text = session.editor.text
    session.close()  # as if killed: nothing saved
    again = session_on(tmp_path, FRAME_PROGRAM)
    again.editor.recover()
    again.teach("second")
    again.close()
    third = session_on(tmp_path, FRAME_PROGRAM)
    third.editor.recover()
    assert "POS first" in third.editor.text and "POS second" in third.editor.text and text != third.editor.text


def test_a_record_torn_by_the_kill_is_skipped(tmp_path) -> None:
    journal = Journal(tmp_path / ".j")
    journal.append("teach a", "POS a = 1\n")
    journal.append("teach b", "POS a = 1\nPOS b = 2\n")
    journal.close()
    with open(tmp_path / ".j", "ab") as handle:
        handle.write(b'{"seq": 3, "action": "teach c", "text": "POS a')  # the kill came mid-write
    entries = read_journal(tmp_path / ".j")
    assert [e.action for e in entries] == ["teach a", "teach b"]


def test_saving_clears_the_journal_and_nothing_is_offered(tmp_path) -> None:
    session = session_on(tmp_path)
    session.teach("p")
    assert journal_path(session.editor.path).exists()
    session.editor.save()
    assert session_on(tmp_path, session.editor.text).editor.pending_recovery() is None


def test_declining_recovery_discards_the_journal(tmp_path) -> None:
    session = session_on(tmp_path)
    session.teach("p")
    session.close()
    again = session_on(tmp_path, FRAME_PROGRAM)
    again.editor.discard_recovery()
    assert again.editor.pending_recovery() is None and again.editor.text == FRAME_PROGRAM


def test_save_writes_atomically_and_refuses_other_suffixes(tmp_path) -> None:
    session = session_on(tmp_path)
    session.teach("p")
    session.editor.save(str(tmp_path / "copy.rpl"))
    assert (tmp_path / "copy.rpl").read_text(encoding="utf-8") == session.editor.text
    assert not [p for p in os.listdir(tmp_path) if p.endswith(".tmp")]
    try:
        session.editor.save(str(tmp_path / "copy.txt"))
    except Exception as error:  # noqa: BLE001
        assert "must end in .rpl" in str(error)
    else:
        raise AssertionError("saving as .txt should be refused")
