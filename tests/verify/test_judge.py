"""Judging a run: expectation, collisions and near misses, baseline slowdowns, runs that never ran; baselines."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from orc_rpl.errors import UsageError
from orc_rpl.verify.judge import Thresholds, baseline_of, judge, load_baseline
from orc_rpl.verify.outcomes import parse_condition
from orc_rpl.verify.programs import Expectation
from orc_rpl.verify.task import RunOutcome

FINISHED = {"status": "finished", "cycle_time_s": 2.0, "motions": 4, "warnings": [], "error": None}


def _judge(outcome: RunOutcome | None, expectation: Expectation = Expectation(), baseline: dict | None = None,
           min_clearance_mm: float = 0.0, clearance_drop_mm: float | None = None):
    return judge("p.rpl", "irb2400", expectation, outcome, 1, "its worker died on every attempt", baseline or {},
                 Thresholds(5.0, min_clearance_mm, clearance_drop_mm))


def _margins(clearance_mm: float) -> dict:
    """A summary's `margins` section: the nearest approach at line 3."""
    near = {"clearance_mm": clearance_mm, "file": "/abs/p.rpl", "line": 3, "column": 1, "robot_body": "link5",
            "obstacle": "table_top", "time_s": 1.0}
    joint = {"joint_margin_deg": 12.5, "joint": 4, "file": "/abs/p.rpl", "line": 2, "column": 1}
    return {"clearance": near, "joint_margin": joint, "motions": [{**joint, **near}]}


def test_a_program_with_a_check_error_is_rejected_with_its_message() -> None:
    outcome = RunOutcome(2, None, "", "p.rpl:3:1: unknown name 'x'\n   3 | MOVE x\norc run: 1 check error; nothing moved\n")
    row = _judge(outcome)
    assert (row.status, row.verdict, row.reasons) == ("rejected", "FAIL", ("expected finished, got rejected",))
    assert "p.rpl:3:1: unknown name 'x'" in row.message
    assert _judge(outcome, Expectation("rejected")).verdict == "ok"


@pytest.mark.parametrize("clearance_mm, minimum_mm, verdict, reason", [
    (50.0, 0.0, "ok", None),
    (50.0, 60.0, "FAIL", "near miss: 50.0 mm, link5 to table_top at p.rpl:3 (t = 1.00 s) (below 60 mm)"),
    (-2.0, 0.0, "FAIL", "collision: link5 to table_top at p.rpl:3 (t = 1.00 s) (2.0 mm deep)"),
])
def test_clearance_fails_collisions_and_near_misses(clearance_mm: float, minimum_mm: float, verdict: str,
                                                    reason: str | None) -> None:
    outcome = RunOutcome(0, {**FINISHED, "margins": _margins(clearance_mm)}, "", "")
    row = _judge(outcome, min_clearance_mm=minimum_mm)
    assert row.verdict == verdict and row.reasons == ((reason,) if reason else ())
    assert (row.clearance_at, row.clearance_bodies, row.margin_at, row.margin_joint) == \
        ("p.rpl:3", ("link5", "table_top"), "p.rpl:2", 4)
    [motion] = row.as_json()["motion_margins"]
    assert (motion["at"], motion["clearance_mm"], motion["joint_margin_deg"]) == ("p.rpl:3", clearance_mm, 12.5)


def test_clearance_against_the_baseline_is_shown_and_fails_only_beyond_the_drop_asked() -> None:
    outcome = RunOutcome(0, {**FINISHED, "margins": _margins(30.0)}, "", "")
    baseline = {"p.rpl [irb2400]": {"cycle_time_s": 2.0, "clearance_mm": 45.0}}
    shown = _judge(outcome, baseline=baseline)
    assert shown.verdict == "ok" and shown.baseline_clearance_mm == 45.0
    row = _judge(outcome, baseline=baseline, clearance_drop_mm=10.0)
    assert row.verdict == "FAIL"
    assert row.reasons == ("clearance 30.0 mm at p.rpl:3, 15.0 mm less than the baseline (45.0 mm)",)
    assert _judge(outcome, baseline=baseline, clearance_drop_mm=20.0).verdict == "ok"


WELDED = {**FINISHED, "process": {"welds": [{"good": True}, {"good": False}], "bulges": [], "seams": [],
                                  "identifications": [], "tunings": [], "faults": []}}


def test_process_figures_are_judged_against_the_header_and_the_baseline() -> None:
    outcome = RunOutcome(0, WELDED, "", "")
    row = _judge(outcome)
    assert row.process_figures == {"welds": 2, "welds_good": 1, "faults_not_caught": 0} and row.verdict == "ok"
    wants_two = Expectation(process=(parse_condition("welds_good = 2", 4), parse_condition("welds >= 2", 5)))
    row = _judge(outcome, wants_two)
    assert row.verdict == "FAIL" and row.reasons == ("expected process welds_good = 2 (header line 4), got 1",)
    assert _judge(outcome, Expectation(process=(parse_condition("burr_left_mm <= 0.1", 2),))).reasons == \
        ("expected process burr_left_mm <= 0.1 (header line 2), the run reported none",)
    before = {"p.rpl [irb2400]": {"cycle_time_s": 2.0, "process": {"welds": 2, "welds_good": 2}}}
    assert _judge(outcome, baseline=before).reasons == ("process welds_good: 1, 2 in the baseline",)
    fewer = {"p.rpl [irb2400]": {"cycle_time_s": 2.0, "process": {"welds": 2, "welds_good": 0}}}
    assert _judge(outcome, baseline=fewer).verdict == "ok", "more good welds than the baseline is no failure"


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
                                                                           "motions": 4, "clearance_mm": None,
                                                                           "clearance_at": ""}}
    welded = _judge(RunOutcome(0, {**WELDED, "margins": _margins(30.0)}, "", ""))
    assert baseline_of([welded])["runs"]["p.rpl [irb2400]"] == {
        "status": "finished", "cycle_time_s": 2.0, "motions": 4, "clearance_mm": 30.0, "clearance_at": "p.rpl:3",
        "process": {"welds": 2, "welds_good": 1, "faults_not_caught": 0}}
    (tmp_path / "other.json").write_text('{"runs": []}', encoding="utf-8")
    with pytest.raises(UsageError, match="is not a baseline written by orc verify --save-baseline"):
        load_baseline(str(tmp_path / "other.json"))
