"""`orc pendant` as a command: usage errors exit 2 with one line naming the problem; recovery answered by flags."""

from __future__ import annotations

import argparse

import pytest

from orc_rpl.cli import main
from orc_rpl.commands.pendant import _ask_recovery
from tests.pendant.support import FRAME_PROGRAM, session_on


@pytest.mark.parametrize("argv, message", [
    (["pendant", "cell.txt"], "'cell.txt': a program file must end in .rpl"),
    (["pendant", "--robot", "puma", "cell.rpl"], "--robot: unknown robot 'puma'"),
    (["pendant", "--world", "nowhere", "cell.rpl"], "--world: 'nowhere' is neither a directory nor a world model file"),
    (["pendant", "bad.rpl"], "bad.rpl:1:12: unexpected end of line"),
], ids=["suffix", "robot", "world", "syntax"])
def test_usage_errors_exit_2_with_a_message(tmp_path, monkeypatch, capsys, argv, message) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "bad.rpl").write_text("MOVE ARM TO\n", encoding="utf-8")
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


@pytest.mark.parametrize("flag, expect_recovered", [("recover", True), ("discard", False)])
def test_recovery_flags_answer_without_asking(tmp_path, flag, expect_recovered) -> None:
    session = session_on(tmp_path)
    session.teach("p9")
    session.close()
    again = session_on(tmp_path, FRAME_PROGRAM)
    args = argparse.Namespace(recover=flag == "recover", discard=flag == "discard")
    _ask_recovery(again, args)
    assert ("POS p9" in again.editor.text) is expect_recovered
    assert again.editor.pending_recovery() is None or expect_recovered


def test_without_a_terminal_the_journal_is_kept_for_later(tmp_path, monkeypatch) -> None:
    session = session_on(tmp_path)
    session.teach("p9")
    session.close()
    again = session_on(tmp_path, FRAME_PROGRAM)
    monkeypatch.setattr("sys.stdin.isatty", lambda: False)
    answer = _ask_recovery(again, argparse.Namespace(recover=False, discard=False))
    assert "start with --recover or --discard" in answer and again.editor.pending_recovery() is not None
