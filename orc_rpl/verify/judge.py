"""Judging a verified run: its row of the table, the expectation of its header, and its baseline."""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any, Mapping

from orc_rpl.errors import UsageError
from orc_rpl.verify.outcomes import against_baseline, figures
from orc_rpl.verify.programs import Expectation
from orc_rpl.verify.task import RunOutcome

BASELINE_VERSION = 1

#: Verdicts: ok, FAIL (exit 1), skipped (the header names other robots), cancelled (Ctrl-C before it ran).
OK, FAIL, SKIPPED, CANCELLED = "ok", "FAIL", "skipped", "cancelled"


@dataclass(frozen=True, slots=True)
class Row:
    """One program on one robot, as the table, the JSON report and JUnit show it."""

    program: str
    robot: str
    status: str                               #: finished, stopped, failed, rejected (exit 2), lost, skipped, cancelled
    exception: str | None = None
    cycle_time_s: float | None = None
    baseline_cycle_time_s: float | None = None
    change_pct: float | None = None           #: cycle time against the baseline, in percent
    motions: int | None = None
    warnings: int = 0
    joint_margin_deg: float | None = None
    margin_joint: int | None = None
    margin_at: str = ""                       #: file:line of the motion statement with the smallest joint margin
    clearance_mm: float | None = None         #: nearest approach of the robot to the cell's objects (negative: collision)
    clearance_at: str = ""                    #: file:line of the motion statement where it came that near
    clearance_bodies: tuple[str, str] | None = None  #: the robot's link (or tool) and the cell's object
    clearance_time_s: float | None = None
    measured: bool = False                    #: margins were measured (a run that moved; clearance None: > 500 mm)
    motion_margins: tuple[dict[str, Any], ...] = ()  #: every motion statement's clearance and joint margin (its line)
    baseline_clearance_mm: float | None = None
    process: Any = None                       #: the run summary's `process` section, when the run has one
    process_figures: dict[str, Any] | None = None  #: its comparable figures (verify.outcomes)
    attempts: int = 1                         #: 2 when its worker died and it ran again
    expected: str = "finished"
    verdict: str = OK
    reasons: tuple[str, ...] = ()
    message: str = ""                         #: the error or the end of the run's output, for failures

    def key(self) -> str:
        return f"{self.program} [{self.robot}]"

    def nearest(self) -> str:
        """Where the robot came nearest to the cell, in words."""
        if self.clearance_bodies is None:
            return ""
        return (f"{self.clearance_bodies[0]} to {self.clearance_bodies[1]} at {self.clearance_at} "
                f"(t = {self.clearance_time_s:.2f} s)")

    def as_json(self) -> dict[str, Any]:
        data = asdict(self)
        data["reasons"], data["motion_margins"] = list(self.reasons), list(self.motion_margins)
        return data


def _message(outcome: RunOutcome) -> str:
    error = (outcome.summary or {}).get("error")
    if error:
        return f"line {error['line']}: {error.get('exception') or 'error'}: {error['message']}"
    lines = [line for line in outcome.stderr.splitlines() if line.strip()]
    return "\n".join(lines[-6:])


def _margins(summary: dict[str, Any], program: str) -> dict[str, Any]:
    """The row's fields from the summary's `margins` section (orc run --margins); places as `program:line` (the
    run was given the program's absolute path, the table shows it as found)."""
    section = summary.get("margins")
    if not isinstance(section, dict) or not section.get("motions"):
        return {}
    fields: dict[str, Any] = {"measured": True, "motion_margins": tuple(
        {**{k: v for k, v in motion.items() if k != "file"}, "at": f"{program}:{motion['line']}"}
        for motion in section["motions"])}
    near, joint = section.get("clearance"), section.get("joint_margin")
    if near is not None:
        fields.update(clearance_mm=near["clearance_mm"], clearance_at=f"{program}:{near['line']}",
                      clearance_bodies=(near["robot_body"], near["obstacle"]), clearance_time_s=near["time_s"])
    if joint is not None:
        fields.update(joint_margin_deg=joint["joint_margin_deg"], margin_joint=joint["joint"],
                      margin_at=f"{program}:{joint['line']}")
    return fields


@dataclass(frozen=True, slots=True)
class Thresholds:
    """What fails a run besides its expectation: slowing down, coming near, losing clearance or process quality."""

    slowdown_pct: float = 5.0
    min_clearance_mm: float = 0.0
    clearance_drop_mm: float | None = None    #: fail when the clearance shrank by more than this (None: reported only)
    process_pct: float = 5.0                  #: process figures worse than the baseline's by more than this fail


def judge(program: str, robot: str, expectation: Expectation, outcome: RunOutcome | None, attempts: int,
          failure: str | None, baseline: Mapping[str, Any], limits: Thresholds = Thresholds()) -> Row:
    """The row of one run: what happened, against what the header expects and the baseline's cycle time,
    clearance and process figures."""
    if outcome is None:
        return Row(program, robot, "lost", attempts=attempts, expected=expectation.outcome, verdict=FAIL,
                   reasons=(f"not run: {failure}",), message=failure or "")
    summary = outcome.summary
    if summary is None:  # exit 2: syntax, check or usage error; nothing moved
        status = "rejected" if outcome.exit_code == 2 else "failed"
        row = Row(program, robot, status, attempts=attempts, expected=expectation.outcome, message=_message(outcome))
    else:
        error = summary.get("error") or {}
        process = summary.get("process")
        row = Row(program, robot, str(summary["status"]), exception=error.get("exception"),
                  cycle_time_s=summary.get("cycle_time_s"), motions=summary.get("motions"),
                  warnings=len(summary.get("warnings", ())), process=process,
                  process_figures=figures(process) if process is not None else None, attempts=attempts,
                  expected=expectation.outcome, message=_message(outcome) if error else "", **_margins(summary, program))
    reasons = []
    if not expectation.met_by(row.status, row.exception):
        got = row.status + (f" ({row.exception})" if row.exception else "")
        reasons.append(f"expected {expectation.outcome}, got {got}")
    for condition in expectation.process:
        why = condition.failure(row.process_figures or {}) if summary is not None else None
        if why is not None:
            reasons.append(why)
    if row.clearance_mm is not None and row.clearance_mm < 0:
        reasons.append(f"collision: {row.nearest()} ({-row.clearance_mm:.1f} mm deep)")
    elif row.clearance_mm is not None and row.clearance_mm < limits.min_clearance_mm:
        reasons.append(f"near miss: {row.clearance_mm:.1f} mm, {row.nearest()} (below {limits.min_clearance_mm:g} mm)")
    saved = baseline.get(row.key(), {})
    before = saved.get("cycle_time_s")
    change = None
    if before is not None and row.cycle_time_s is not None and before > 0:
        change = 100.0 * (row.cycle_time_s - before) / before
        if change > limits.slowdown_pct:
            reasons.append(f"{change:.1f} % slower than the baseline ({before:.3f} s)")
    clearance_before = saved.get("clearance_mm")
    if limits.clearance_drop_mm is not None and clearance_before is not None and row.measured:
        now = row.clearance_mm  # None: nothing within reach of the measurement any more, no drop
        if now is not None and clearance_before - now > limits.clearance_drop_mm:
            reasons.append(f"clearance {now:.1f} mm at {row.clearance_at}, {clearance_before - now:.1f} mm less than "
                           f"the baseline ({clearance_before:.1f} mm)")
    if row.process_figures is not None or saved.get("process"):
        reasons += against_baseline(row.process_figures or {}, saved.get("process") or {}, limits.process_pct)
    return replace(row, baseline_cycle_time_s=before, change_pct=change, baseline_clearance_mm=clearance_before,
                   verdict=FAIL if reasons else OK, reasons=tuple(reasons))


def skipped(program: str, robot: str, expectation: Expectation) -> Row:
    """A program whose header names the robots it runs on, and not this one."""
    return Row(program, robot, "skipped", expected=expectation.outcome, verdict=SKIPPED,
               reasons=(f"runs only on {', '.join(expectation.robots)}",))


def cancelled(program: str, robot: str, expectation: Expectation) -> Row:
    """A run Ctrl-C cancelled before it finished."""
    return Row(program, robot, "cancelled", expected=expectation.outcome, verdict=CANCELLED)


def load_baseline(path: str) -> dict[str, Any]:
    """The runs of a baseline written by `--save-baseline` (a UsageError naming the file otherwise)."""
    try:
        data = json.loads(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise UsageError(f"--baseline: '{path}' does not exist") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
        raise UsageError(f"--baseline: cannot read '{path}': {error}") from None
    if not isinstance(data, dict) or data.get("version") != BASELINE_VERSION or not isinstance(data.get("runs"), dict):
        raise UsageError(f"--baseline: '{path}' is not a baseline written by orc verify --save-baseline")
    return data["runs"]


def baseline_of(rows: list[Row]) -> dict[str, Any]:
    """The baseline of these rows: status, cycle time, motions, clearance and process figures of every run that ran."""
    runs = {row.key(): {"status": row.status, "cycle_time_s": row.cycle_time_s, "motions": row.motions,
                        "clearance_mm": row.clearance_mm, "clearance_at": row.clearance_at,
                        **({"process": row.process_figures} if row.process_figures else {})}
            for row in rows if row.verdict in (OK, FAIL) and row.status != "lost"}
    return {"version": BASELINE_VERSION, "runs": dict(sorted(runs.items()))}
