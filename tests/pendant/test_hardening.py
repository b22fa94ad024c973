"""The pendant under careless use: no terminal, files that are not programs, a journal that cannot be written where
it belongs; every case an answer naming the problem, never a traceback, and no edit lost."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from orc_rpl.cli import main
from orc_rpl.pendant.commands import run_line
from orc_rpl.pendant.journal import JournalError, journal_beside, journal_path
from tests.pendant.support import FRAME_PROGRAM, LINE_MOVE_POS1, session_on

ORC = [sys.executable, "-m", "orc_rpl"]


def _pendant(tmp_path: Path, script: str, *options: str) -> subprocess.CompletedProcess[str]:
    """`orc pendant cell.rpl` with `script` on standard input (not a terminal), on the fast kinematic robot."""
    env = {**os.environ, "XDG_STATE_HOME": str(tmp_path / "state")}
    return subprocess.run([*ORC, "pendant", "cell.rpl", "--backend", "kinematic", *options], input=script,
                          capture_output=True, text=True, cwd=tmp_path, env=env, timeout=120)


def test_without_a_terminal_each_line_runs_as_typed_and_a_failed_line_makes_exit_1(tmp_path: Path) -> None:
    (tmp_path / "cell.rpl").write_text(FRAME_PROGRAM, encoding="utf-8")
    done = _pendant(tmp_path, "MOVE ARM TO pos0\n:teach corner\n:save\n:positions\n")
    assert done.returncode == 0, done.stderr
    assert "taught POS corner" in done.stdout and "corner" in done.stdout.splitlines()[-1]
    assert "POS corner = POSE(800mm, -300mm, 800mm" in (tmp_path / "cell.rpl").read_text(encoding="utf-8")
    failed = _pendant(tmp_path, "MOVE ARM TO nowhere\n:positions\n")
    assert failed.returncode == 1 and "Traceback" not in failed.stderr
    assert "<stdin>:1: error in 'MOVE ARM TO nowhere'" in failed.stderr and "pos0" in failed.stdout


def test_a_script_does_not_bury_a_killed_sessions_edits(tmp_path: Path) -> None:
    (tmp_path / "cell.rpl").write_text(FRAME_PROGRAM, encoding="utf-8")
    first = _pendant(tmp_path, ":teach kept\n")
    assert first.returncode == 0 and "unsaved edits of cell.rpl are kept in its journal" in first.stderr
    second = _pendant(tmp_path, ":teach other\n")
    assert second.returncode == 2 and "start with --recover or --discard" in second.stderr
    recovered = _pendant(tmp_path, ":save\n", "--recover")
    assert recovered.returncode == 0
    assert "POS kept" in (tmp_path / "cell.rpl").read_text(encoding="utf-8")


@pytest.mark.parametrize("make, message", [
    (lambda p: os.mkfifo(p), "not a regular file"),
    (lambda p: p.write_bytes(b"MOVE ARM TO \xff\xfe\n"), "it is not a UTF-8 text file"),
], ids=["fifo", "binary"])
def test_a_file_that_is_not_a_program_is_refused_up_front(tmp_path, monkeypatch, capsys, make, message) -> None:
    monkeypatch.chdir(tmp_path)
    make(tmp_path / "cell.rpl")
    assert main(["pendant", "cell.rpl", "--backend", "kinematic"]) == 2
    err = capsys.readouterr().err
    assert f"cannot open cell.rpl: {message}" in err and "Traceback" not in err


def test_a_folder_in_the_journals_place_sends_the_journal_to_the_state_folder(tmp_path, monkeypatch) -> None:
    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path / "state"))
    journal_beside(tmp_path / "cell.rpl").mkdir()
    session = session_on(tmp_path)
    session.teach("p9")
    where = journal_path(session.editor.path)
    assert where.is_file() and str(where).startswith(str(tmp_path / "state"))
    assert any("edits are journaled in" in line for line in session.events.lines)
    session.close()  # as if killed: nothing saved
    again = session_on(tmp_path, FRAME_PROGRAM)
    assert again.editor.pending_recovery() is not None
    again.editor.recover()
    assert "POS p9" in again.editor.text


def test_a_journal_that_cannot_be_written_is_said_and_the_edit_stands(tmp_path, monkeypatch) -> None:
    session = session_on(tmp_path)

    def full(fd: int, data: bytes) -> int:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "write", full)
    with pytest.raises(JournalError, match="teach p9: done, but the journal .* cannot be written .*:save now"):
        session.teach("p9")
    monkeypatch.undo()
    assert "POS p9" in session.editor.text and session.editor.modified
    session.editor.save()
    assert "POS p9" in (tmp_path / "cell.rpl").read_text(encoding="utf-8")


def test_a_typed_statement_error_points_at_the_offending_word(tmp_path) -> None:
    session = session_on(tmp_path)
    before = session.robot.joints()
    outcome = run_line(session, "MOVE ARM TO nowhere")
    assert outcome.error and "<typed>:1:13: undefined name 'nowhere'" in outcome.text
    assert outcome.text.splitlines()[-1].strip() == "|             ^^^^^^^"
    outcome = run_line(session, "MOVE ARM TO pos1")  # outside the FRAME block: relative to world
    assert outcome.error and "<typed>:1:13: target 'pos1' is relative to base_plate" in outcome.text
    assert session.robot.joints() == before  # nothing moved
    session.editor.goto(LINE_MOVE_POS1)
    assert not run_line(session, "MOVE ARM TO pos1").error  # inside it, the same words are right


def test_assignments_typed_earlier_are_known_to_the_next_typed_statement(tmp_path) -> None:
    session = session_on(tmp_path)
    assert not run_line(session, "n = 3").error
    outcome = run_line(session, "PRINT n * 2")
    assert not outcome.error and session.execution.printed[-1] == "6"


def test_no_surprises_goto_help_and_the_jog_space(tmp_path) -> None:
    session = session_on(tmp_path)
    assert run_line(session, ":goto 6").text == "line 6 holds no statement; cursor at line 7"  # line 6 is blank
    assert ":quit | quit!" in run_line(session, ":help").text
    assert ":quit!" in run_line(session, ":help quit!").text
    run_line(session, ":jog world z +1mm")
    assert (session.jogger.space_label(), session.jogger.axis_label()) == ("world", "z")


def test_a_jog_amount_that_is_not_finite_is_refused_and_nothing_moves(tmp_path) -> None:
    session = session_on(tmp_path)
    before = session.robot.joints()
    outcome = run_line(session, ":jog tool z -1e999mm")
    assert outcome.error and "is not a finite number" in outcome.text
    assert session.robot.joints() == before
