"""The thesis programs print their outcome as the application computed it: the same figures as the summary's."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from orc_rpl.cli import main

ROOT = Path(__file__).resolve().parents[2]


def run(name: str, prefix: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> tuple[str, dict]:
    """`orc run` of programs/online/NAME: the printed line starting with `prefix` and the summary's process section."""
    summary = tmp_path / "summary.json"
    code = main(["run", str(ROOT / "programs/online" / name), "--summary-json", str(summary)])
    out, err = capsys.readouterr()
    assert code == 0, err
    printed = next(line for line in out.splitlines() if line.startswith(prefix))
    return printed, json.loads(summary.read_text())["process"]


@pytest.mark.sim
@pytest.mark.parametrize("name", ["thesis_2_1_grindmove.rpl", "thesis_3_1_deburring.rpl"])
def test_the_thesis_programs_print_what_the_summary_says(name: str, tmp_path: Path,
                                                         capsys: pytest.CaptureFixture[str]) -> None:
    printed, process = run(name, "bulges caught:", tmp_path, capsys)
    words, bulges = printed.split(), process["bulges"]
    assert int(words[2]) == len(bulges) >= 1
    assert float(words[-1]) == pytest.approx(1000 * max(b["left_m"] for b in bulges), abs=1e-9)


@pytest.mark.sim
@pytest.mark.parametrize("name", ["thesis_2_4_calibrate.rpl", "thesis_2_4_tuned_move.rpl"])
def test_the_calibrate_programs_print_the_tuning_the_summary_records(name: str, tmp_path: Path,
                                                                      capsys: pytest.CaptureFixture[str]) -> None:
    printed, process = run(name, "BoltTuning:", tmp_path, capsys)
    (tuning,) = process["tunings"]
    assert printed == f"BoltTuning: {tuning['label']}" and tuning["samples"] > 0
