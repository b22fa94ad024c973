"""A parameter sweep: the grid of runs (CONST values x seeds x plant variations) and its table as CSV and JSON lines."""

from __future__ import annotations

import csv
import itertools
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

from orc_rpl.errors import UsageError
from orc_rpl.verify.outcomes import figures
from orc_rpl.verify.task import RunOutcome, RunSpec


@dataclass(frozen=True, slots=True)
class Variation:
    """A named variation of the plant: further `orc run` options (e.g. `--plant ideal`)."""

    name: str
    options: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class Point:
    """One point of the grid: CONST values, a seed (None: orc run's default) and a variation (None: none)."""

    settings: tuple[tuple[str, str], ...]
    seed: int | None
    variation: Variation | None


def split_values(text: str) -> tuple[str, tuple[str, ...]]:
    """`--set Vmax=1mps,1.5mps` -> ("Vmax", ("1mps", "1.5mps")); commas inside brackets stay in the value."""
    name, equals, values = text.partition("=")
    if not equals or not name.strip():
        raise UsageError(f"--set: expected NAME=V1,V2,..., got {text!r}")
    parts, depth, current = [], 0, ""
    for char in values:
        if char in "([":
            depth += 1
        elif char in ")]":
            depth -= 1
        if char == "," and depth == 0:
            parts.append(current.strip())
            current = ""
        else:
            current += char
    parts.append(current.strip())
    if not all(parts):
        raise UsageError(f"--set {name}: an empty value in {values!r}")
    return name.strip(), tuple(parts)


def grid(sets: Sequence[str], seeds: int | None, variations: Sequence[Variation]) -> list[Point]:
    """Every combination, the first --set varying slowest; seeds 0..N-1 when asked."""
    axes = [split_values(text) for text in sets]
    names = [name for name, _ in axes]
    if len(set(names)) != len(names):
        raise UsageError("--set: a CONST is named twice")
    points = []
    for values in itertools.product(*(values for _, values in axes)):
        for seed in range(seeds) if seeds is not None else (None,):
            for variation in variations or (None,):
                points.append(Point(tuple(zip(names, values)), seed, variation))
    return points


def spec_of(point: Point, program: str, robot: str, world: str | None, options: tuple[str, ...]) -> RunSpec:
    """The run of a point: its CONST values as --set, its seed as --seed, its variation's options."""
    extra = options + (("--seed", str(point.seed)) if point.seed is not None else ())
    extra += point.variation.options if point.variation is not None else ()
    return RunSpec(program, robot, world, tuple(f"{name}={value}" for name, value in point.settings), extra)


def _flat(prefix: str, value: Any, into: dict[str, Any]) -> None:
    if isinstance(value, dict):
        for key, inner in value.items():
            _flat(f"{prefix}.{key}", inner, into)
    elif isinstance(value, list):  # records of a process (welds, identifications...): one column each, by index
        for index, inner in enumerate(value):
            _flat(f"{prefix}.{index}", inner, into)
    elif isinstance(value, (int, float, str, bool)) or value is None:
        into[prefix] = value


def _margin_columns(section: Any) -> dict[str, Any]:
    """The nearest approach and the smallest joint margin of a run, each with the line of its motion statement."""
    near = (section or {}).get("clearance") or {}
    joint = (section or {}).get("joint_margin") or {}
    return {"clearance_mm": near.get("clearance_mm"), "clearance_line": near.get("line"),
            "clearance_bodies": f"{near['robot_body']}/{near['obstacle']}" if near else None,
            "joint_margin_deg": joint.get("joint_margin_deg"), "joint_margin_line": joint.get("line")}


def record_of(index: int, point: Point, outcome: RunOutcome | None, attempts: int, failure: str | None) -> dict[str, Any]:
    """One line of the table: the point's parameters, then what the run gave (process outcomes flattened)."""
    record: dict[str, Any] = {"run": index, **dict(point.settings)}
    if point.seed is not None:
        record["seed"] = point.seed
    if point.variation is not None:
        record["variation"] = point.variation.name
    summary = (outcome.summary if outcome is not None else None) or {}
    error = summary.get("error") or {}
    status = summary.get("status") or ("lost" if outcome is None else "rejected" if outcome.exit_code == 2 else "failed")
    record.update({"status": status, "exception": error.get("exception"), "cycle_time_s": summary.get("cycle_time_s"),
                   "motions": summary.get("motions"), "warnings": len(summary.get("warnings", ())),
                   **_margin_columns(summary.get("margins")), "attempts": attempts})
    if "process" in summary:
        record.update({f"figure.{name}": value for name, value in figures(summary["process"]).items()})
        _flat("process", summary["process"], record)
    if outcome is None:
        record["failure"] = failure
    elif error or outcome.exit_code == 2:
        lines = outcome.stderr.strip().splitlines()
        record["message"] = error.get("message") or (lines[-1] if lines else "")
    return record


def write_table(records: list[dict[str, Any]], csv_path: Path, jsonl_path: Path) -> None:
    """The records in run order, as CSV (the union of their columns) and as JSON lines."""
    columns: list[str] = []
    for record in records:
        columns.extend(key for key in record if key not in columns)
    with csv_path.open("w", newline="", encoding="utf-8") as stream:
        writer = csv.DictWriter(stream, fieldnames=columns)
        writer.writeheader()
        writer.writerows(records)
    jsonl_path.write_text("".join(json.dumps(record) + "\n" for record in records), encoding="utf-8")
