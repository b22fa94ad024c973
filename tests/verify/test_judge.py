"""Judging a run: expectation, collisions and near misses, baseline slowdowns, runs that never ran; baselines."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from orc_rpl.errors import UsageError
from orc_rpl.verify.judge import baseline_of, judge, load_baseline
from orc_rpl.verify.programs import Expectation
from orc_rpl.verify.task import RunOutcome

FINISHED = {"status": "finished", "cycle_time_s": 2.0, "motions": 4, "warnings": [], "error": None}


def _judge(outcome: RunOutcome | None, expectation: Expectation = Expectation(), baseline: dict | None = None,
           min_clearance_mm: float = 0.0):
    return judge("p.rpl", "irb2400", expectation, outcome, 1, "its worker died on every attempt", baseline or {},
                 5.0, min_clearance_mm)


def test_a_program_with_a_check_error_is_rejected_with_its_message() -> None:
    outcome = RunOutcome(2, None, "", "p.rpl:3:1: unknown name 'x'\n   3 | MOVE x\norc run: 1 check error; nothing moved\n")
    row = _judge(outcome)
    assert (row.status, row.verdict, row.reasons) == ("rejected", "FAIL", ("expected finished, got rejected",))
    assert "p.rpl:3:1: unknown name 'x'" in row.message
    assert _judge(outcome, Expectation("rejected")).verdict == "ok"


@pytest.mark.parametrize("clearance_m, minimum_mm, verdict, reason", [
    (0.05, 0.0, "ok", None),
    (0.05, 60.0, "FAIL", "near miss: 50.0 mm, link5 to table_top at 1.00 s (below 60 mm)"),
    (-0.002, 0.0, "FAIL", "collision: link5 to table_top at 1.00 s (2.0 mm deep)"),
])
def test_clearance_fails_collisions_and_near_misses(clearance_m: float, minimum_mm: float, verdict: str,
                                                    reason: str | None) -> None:
    outcome = RunOutcome(0, FINISHED, "", "", clearance_m=clearance_m, nearest="link5 to table_top at 1.00 s")
    row = _judge(outcome, min_clearance_mm=minimum_mm)
    assert row.verdict == verdict and row.reasons == ((reason,) if reason else ())


def test_slower_than_the_baseline_by_more_than_the_threshold_fails() -> None:
    outcome = RunOutcome(0, FINISHED, "", "")
    assert _judge(outcome, baseline={"p.rpl [irb2400]": {"cycle_time_s": 1.92}}).verdict == "ok"  # 4.2 % slower
    row = _judge(outcome, baseline={"p.rpl [irb2400]": {"cycle_time_s": 1.8}})
    assert row.verdict == "FAIL" and row.reasons == ("11.1 % slower than the baseline (1.800 s)",)


def test_a_run_that_never_ran_is_lost_not_dropped() -> None:
    row = _judge(None)
    assert (row.status, row.verdict, row.reasons) == ("lost", "FAIL", ("not run: its worker died on every attempt",))


def test_baselines_round_trip_and_foreign_files_are_refused(tmp_path: Path) -> None:
    row = _judge(RunOutcome(0, FINISHED, "", ""))
    (tmp_path / "b.json").write_text(json.dumps(baseline_of([row])), encoding="utf-8")
    assert load_baseline(str(tmp_path / "b.json")) == {"p.rpl [irb2400]": {"status": "finished", "cycle_time_s": 2.0,
                                                                           "motions": 4}}
    (tmp_path / "other.json").write_text('{"runs": []}', encoding="utf-8")
    with pytest.raises(UsageError, match="is not a baseline written by orc verify --save-baseline"):
        load_baseline(str(tmp_path / "other.json"))
