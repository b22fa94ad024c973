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


def _properties(row: Row) -> dict[str, str]:
    """What a CI system can chart per run: cycle time, clearance and joint margin with their lines, process figures."""
    values: dict[str, str] = {}
    if row.cycle_time_s is not None:
        values["cycle_time_s"] = f"{row.cycle_time_s:.6f}"
    if row.clearance_mm is not None and row.clearance_bodies is not None:
        values.update(clearance_mm=f"{row.clearance_mm:.3f}", clearance_at=row.clearance_at,
                      clearance_bodies=" to ".join(row.clearance_bodies))
    if row.joint_margin_deg is not None:
        values.update(joint_margin_deg=f"{row.joint_margin_deg:.3f}", joint=f"j{row.margin_joint}",
                      joint_margin_at=row.margin_at)
    for name, value in (row.process_figures or {}).items():
        values[f"process.{name}"] = str(value)
    return values


def write_junit(path: str, rows: list[Row], wall_s: float) -> None:
    """A JUnit XML test suite: one test case per program and robot, failures with their reasons."""
    tally = counts(rows)
    suite = ET.Element("testsuite", name="orc verify", tests=str(tally["runs"]), failures=str(tally["failed"]),
                       errors="0", skipped=str(tally["skipped"] + tally["cancelled"]), time=f"{wall_s:.3f}")
    for row in rows:
        case = ET.SubElement(suite, "testcase", classname=row.robot, name=row.program,
                             time=f"{row.cycle_time_s or 0.0:.3f}")
        figures = _properties(row)
        if figures:
            properties = ET.SubElement(case, "properties")
            for name, value in figures.items():
                ET.SubElement(properties, "property", name=name, value=value)
        if row.verdict == FAIL:
            failure = ET.SubElement(case, "failure", message="; ".join(row.reasons))
            failure.text = row.message
        elif row.verdict in (SKIPPED, CANCELLED):
            ET.SubElement(case, "skipped", message="; ".join(row.reasons) or row.verdict)
    ET.indent(suite)
    Path(path).write_text('<?xml version="1.0" encoding="utf-8"?>\n' + ET.tostring(suite, encoding="unicode") + "\n",
                          encoding="utf-8")
