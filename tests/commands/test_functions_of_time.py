"""A FUNC of t as a motion target: the TCP follows f(t) for the motion's TIME (a part on a moving conveyor)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from orc_rpl.cli import main

PROGRAM = """\
POS start = POSE(800mm, 0, 900mm, 0, 180deg, 0)
FUNC conveyor(t)
    RETURN OFFS(start, 0.1mps * t, 0, 0)
ENDFUNC
MOVE ARM TO start
LMOVE ARM TO conveyor WITH TIME = 2s
"""


def test_a_function_of_time_needs_the_motions_duration(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    program = tmp_path / "prog.rpl"
    program.write_text(PROGRAM.replace(" WITH TIME = 2s", ""))
    assert main(["check", str(program)]) == 2
    out = capsys.readouterr().out
    assert f"{program}:6:14: FUNC conveyor(t) is a function of time: the motion needs its duration" in out
    assert "add WITH TIME = 5s" in out


def test_the_tcp_follows_a_function_of_time_for_the_motions_time(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    summaries = []
    for text in (PROGRAM.rsplit("LMOVE", 1)[0], PROGRAM):
        program = tmp_path / "prog.rpl"
        program.write_text(text)
        summary = tmp_path / "summary.json"
        assert main(["run", str(program), "--plant", "ideal", "--summary-json", str(summary)]) == 0, capsys.readouterr().err
        summaries.append(json.loads(summary.read_text()))
    duration_s = summaries[1]["cycle_time_s"] - summaries[0]["cycle_time_s"]
    assert 2.0 <= duration_s < 2.25  # its TIME, then settling at the FINE end
    tcp = summaries[1]["final_tcp"]
    assert tcp["x_m"] == pytest.approx(1.0, abs=1e-3) and tcp["y_m"] == pytest.approx(0.0, abs=1e-3)
