"""`orc check` and `orc fmt` as a user runs them: exit codes, messages on the right stream, atomic --write."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from orc_rpl.cli import main
from tests.conftest import online_programs


def orc(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "orc_rpl", *args], capture_output=True, text=True, timeout=60)


def test_check_clean_programs_exits_0() -> None:
    result = orc("check", *map(str, online_programs()))
    assert result.returncode == 0, result.stdout + result.stderr
    assert "no errors" in result.stderr


def test_check_reports_every_error_with_caret_and_exits_2(tmp_path: Path) -> None:
    program = tmp_path / "bad.rpl"
    program.write_text("MOVE ARM TO nowhere\nWAIT 3N\n")
    result = orc("check", str(program))
    assert result.returncode == 2
    assert f"{program}:1:13: undefined name 'nowhere'" in result.stdout
    assert f"{program}:2:6: WAIT expects a time, got a force" in result.stdout
    assert "      |      ^^" in result.stdout
    assert "Traceback" not in result.stderr


def test_missing_file_is_a_one_line_error(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check", str(tmp_path / "none.rpl")]) == 2
    err = capsys.readouterr().err
    assert "cannot read" in err and "none.rpl" in err and "no such file" in err


def test_unknown_suffix_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    other = tmp_path / "prog.txt"
    other.write_text("STOP\n")
    assert main(["check", str(other)]) == 2
    assert "unknown program suffix" in capsys.readouterr().err


def test_fmt_prints_check_flags_and_write_rewrites(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    program = tmp_path / "p.rpl"
    program.write_text("x=1   -- one\nIF x=1 THEN\nSTOP\nENDIF\n")
    assert main(["fmt", str(program)]) == 0
    canonical = "x = 1  -- one\nIF x = 1 THEN\n    STOP\nENDIF\n"
    assert capsys.readouterr().out == canonical
    assert main(["fmt", "--check", str(program)]) == 1
    assert main(["fmt", "--write", str(program)]) == 0
    assert program.read_text() == canonical
    assert main(["fmt", "--check", str(program)]) == 0
    assert [p.name for p in tmp_path.iterdir()] == ["p.rpl"], "no temporary file may be left behind"


def test_fmt_leaves_a_file_with_syntax_errors_untouched(tmp_path: Path) -> None:
    program = tmp_path / "p.rpl"
    original = "IF x THEN\nMOVE\n"
    program.write_text(original)
    result = orc("fmt", "--write", str(program))
    assert result.returncode == 2
    assert program.read_text() == original
    assert "nothing was changed" in result.stderr


def test_write_is_atomic_when_the_write_fails(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from orc_rpl import atomic

    program = tmp_path / "p.rpl"
    program.write_text("x=1\n")

    def broken_fsync(fd: int) -> None:
        raise OSError("disk full")

    monkeypatch.setattr(atomic.os, "fsync", broken_fsync)
    with pytest.raises(OSError):
        atomic.write_text_atomic(program, "x = 1\n")
    assert program.read_text() == "x=1\n"
    assert [p.name for p in tmp_path.iterdir()] == ["p.rpl"]


def test_python_dash_m_and_no_command_shows_help() -> None:
    result = orc()
    assert result.returncode == 2
    assert "usage: orc" in result.stderr


def test_an_offline_program_without_a_world_is_said_to_be_checked_for_syntax_only(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    program = tmp_path / "p.orl"
    program.write_text("start = pose(0.8, 0, 0.6, 0, 180deg, 0)\nlmove arm to start\n")
    assert main(["check", str(program)]) == 0
    out, err = capsys.readouterr()
    assert f"{program}:1:1: syntax only" in out and "--world" in out
    assert "1 file checked (1 for syntax only), no errors" in err
    world = Path(__file__).resolve().parents[2] / "worlds" / "cell_thesis.yaml"
    assert main(["check", str(program), "--world", str(world)]) == 2
    out, _ = capsys.readouterr()
    assert "undefined routine or function 'pose'" in out and "unknown tool 'arm'" in out
