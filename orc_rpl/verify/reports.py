"""What `orc verify` writes for machines: the JSON report, JUnit XML for CI systems, and baselines."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

from orc_rpl.verify.judge import CANCELLED, FAIL, SKIPPED, Row, baseline_of


def counts(rows: list[Row]) -> dict[str, int]:
    """How many runs passed, failed, were skipped and were cancelled."""
    verdicts = [row.verdict for row in rows]
    return {"runs": len(rows), "ok": verdicts.count("ok"), "failed": verdicts.count(FAIL),
            "skipped": verdicts.count(SKIPPED), "cancelled": verdicts.count(CANCELLED)}


def write_json(path: str, rows: list[Row], extra: dict[str, Any]) -> None:
    """Every row, the counts, and what the run was (workers, scheduler, threshold)."""
    data = {**extra, "counts": counts(rows), "runs": [row.as_json() for row in rows]}
    Path(path).write_text(json.dumps(data, indent=2) + "\n", encoding="utf-8")


def write_baseline(path: str, rows: list[Row]) -> None:
    Path(path).write_text(json.dumps(baseline_of(rows), indent=2) + "\n", encoding="utf-8")


def write_junit(path: str, rows: list[Row], wall_s: float) -> None:
    """A JUnit XML test suite: one test case per program and robot, failures with their reasons."""
    tally = counts(rows)
    suite = ET.Element("testsuite", name="orc verify", tests=str(tally["runs"]), failures=str(tally["failed"]),
                       errors="0", skipped=str(tally["skipped"] + tally["cancelled"]), time=f"{wall_s:.3f}")
    for row in rows:
        case = ET.SubElement(suite, "testcase", classname=row.robot, name=row.program,
                             time=f"{row.cycle_time_s or 0.0:.3f}")
        if row.verdict == FAIL:
            failure = ET.SubElement(case, "failure", message="; ".join(row.reasons))
            failure.text = row.message
        elif row.verdict in (SKIPPED, CANCELLED):
            ET.SubElement(case, "skipped", message="; ".join(row.reasons) or row.verdict)
    ET.indent(suite)
    Path(path).write_text('<?xml version="1.0" encoding="utf-8"?>\n' + ET.tostring(suite, encoding="unicode") + "\n",
                          encoding="utf-8")
