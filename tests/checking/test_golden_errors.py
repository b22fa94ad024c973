"""`orc check` on broken programs: the exact text a user reads (file:line:col, message, caret, hint), kept as golden files."""

from __future__ import annotations

from pathlib import Path

import pytest

from orc_rpl.cli import main

GOLDEN = Path(__file__).parent / "golden"
PROGRAMS = sorted(GOLDEN.glob("*.rpl"))


@pytest.mark.parametrize("program", PROGRAMS, ids=[p.stem for p in PROGRAMS])
def test_check_prints_the_golden_errors(program: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(GOLDEN.parents[2])
    assert main(["check", str(program.relative_to(GOLDEN.parents[2]))]) == 2
    assert capsys.readouterr().out == program.with_suffix(".out").read_text()


CLEAN = """\
ENUM Part = NoObject, Bolt
POS start = POSE(0.8, 0.1, 0.6, 0, 180deg, 0)
MOVE ARM TO start
  -- slowly: a comment line between a motion and its continuation
  WITH SPEED = 0.2mps
PRINT HERE.y > 0, HERE.y - 0.1 < 1mm, LEN("abcd"), Bolt, Part
"""


def test_small_gaps_check_clean_and_run(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    program = tmp_path / "gaps.rpl"
    program.write_text(CLEAN)
    assert main(["check", str(program)]) == 0
    assert main(["run", str(program)]) == 0
    assert capsys.readouterr().out.splitlines()[0] == "TRUE TRUE 4 Bolt Part"
