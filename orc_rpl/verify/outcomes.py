"""Process outcomes as figures that can be compared: from a run's `process` section, against a baseline or a header."""

from __future__ import annotations

import operator
import re
from dataclasses import dataclass
from typing import Any, Callable

#: Figures worse than the baseline by more than this (relative) fail; counts and texts must match exactly.
FLOAT_ABS_TOLERANCE = 1e-6


@dataclass(frozen=True, slots=True)
class Figure:
    """One outcome figure: its name, how it is read from the section, and which way is better."""

    name: str
    better: str                                  #: "higher", "lower" or "same" (a count, the parts named)
    read: Callable[[dict[str, Any]], Any]        #: section -> value; only called when `present` holds
    present: Callable[[dict[str, Any]], bool]
    help: str


def _records(kind: str) -> Callable[[dict[str, Any]], bool]:
    return lambda section: bool(section.get(kind))


FIGURES: tuple[Figure, ...] = (
    Figure("welds", "same", lambda s: len(s["welds"]), _records("welds"), "spot welds made"),
    Figure("welds_good", "higher", lambda s: sum(1 for w in s["welds"] if w["good"]), _records("welds"),
           "welds within the gun's speed and offset limits"),
    Figure("bulges", "same", lambda s: len(s["bulges"]), _records("bulges"), "burrs (bulges) caught while grinding"),
    Figure("bulges_within_tolerance", "higher", lambda s: sum(1 for b in s["bulges"] if b["within_tolerance"]),
           _records("bulges"), "burrs ground to within the tolerance"),
    Figure("burr_left_mm", "lower", lambda s: round(1000 * max(b["left_m"] for b in s["bulges"]), 6),
           _records("bulges"), "the highest burr left after grinding (mm)"),
    Figure("seams", "same", lambda s: len(s["seams"]), _records("seams"), "seams tracked"),
    Figure("seam_error_max_mm", "lower", lambda s: round(1000 * max(x["max_m"] for x in s["seams"]), 6),
           _records("seams"), "the laser's largest error while tracking a seam (mm)"),
    Figure("parts", "same", lambda s: ",".join(i["part"] or "?" for i in s["identifications"]),
           _records("identifications"), "the parts identified, in order (? where uncertain)"),
    Figure("identification_confidence", "higher", lambda s: round(min(i["confidence"] for i in s["identifications"]), 6),
           _records("identifications"), "the lowest confidence of an identification"),
    Figure("tunings", "same", lambda s: len(s["tunings"]), _records("tunings"), "tunings (CALIBRATE) made"),
    Figure("faults_not_caught", "lower", lambda s: sum(1 for f in s["faults"] if not f.get("caught", False)),
           lambda s: True, "process faults the program did not catch"),
)
BY_NAME = {figure.name: figure for figure in FIGURES}


def figures(section: dict[str, Any] | None) -> dict[str, Any]:
    """The figures of a run's `process` section (those of the processes it ran); empty when it ran none."""
    if not isinstance(section, dict):
        return {}
    values = {}
    for figure in FIGURES:
        try:
            if figure.present(section):
                values[figure.name] = figure.read(section)
        except (KeyError, TypeError, ValueError):  # a section of another shape: that figure is not given
            continue
    return values


def _worse(figure: Figure, now: Any, before: Any, tolerance_pct: float) -> bool:
    if figure.better == "same" or not isinstance(now, (int, float)) or not isinstance(before, (int, float)):
        return now != before
    slack = FLOAT_ABS_TOLERANCE + (abs(before) * tolerance_pct / 100 if isinstance(before, float) else 0.0)
    return now < before - slack if figure.better == "higher" else now > before + slack


def against_baseline(now: dict[str, Any], before: dict[str, Any], tolerance_pct: float) -> list[str]:
    """Why these figures are worse than the baseline's (empty: as good): counts and parts must be the same, the
    others no worse than `tolerance_pct` percent."""
    reasons = []
    for name, value in before.items():
        figure = BY_NAME.get(name)
        if figure is None:
            continue
        if name not in now:
            reasons.append(f"process {name}: none now, {value} in the baseline")
        elif _worse(figure, now[name], value, tolerance_pct):
            reasons.append(f"process {name}: {now[name]}, {value} in the baseline")
    return reasons


_OPERATORS: dict[str, Callable[[Any, Any], bool]] = {
    "<=": operator.le, ">=": operator.ge, "!=": operator.ne, "=": operator.eq, "<": operator.lt, ">": operator.gt}
_CONDITION = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)\s*(<=|>=|!=|=|<|>)\s*([^=<>!\s].*?)\s*$")


@dataclass(frozen=True, slots=True)
class Condition:
    """`-- expect: welds_good = 4` in a program's header: a figure, a comparison and a value."""

    name: str
    op: str
    value: float | str
    line: int

    def text(self) -> str:
        return f"{self.name} {self.op} {self.value:g}" if isinstance(self.value, float) else \
            f"{self.name} {self.op} {self.value}"

    def failure(self, values: dict[str, Any]) -> str | None:
        """Why the run's figures do not meet the condition, or None."""
        if self.name not in values:
            return f"expected process {self.text()} (header line {self.line}), the run reported none"
        got = values[self.name]
        if isinstance(self.value, float) != isinstance(got, (int, float)):
            return f"expected process {self.text()} (header line {self.line}), got {got}"
        return None if _OPERATORS[self.op](got, self.value) else \
            f"expected process {self.text()} (header line {self.line}), got {got}"


def parse_condition(text: str, line: int) -> Condition:
    """A header's condition; ValueError with what is wrong (the caller names the file and line)."""
    match = _CONDITION.match(text)
    if match is None:
        raise ValueError(f"'expect:' with a comparison takes NAME OP VALUE (OP one of =, !=, <, <=, >, >=), "
                         f"got {text!r}")
    name, op, value = match.groups()
    if name not in BY_NAME:
        raise ValueError(f"'expect:' names an unknown process figure {name!r}; known: {', '.join(BY_NAME)}")
    try:
        number: float | str = float(value)
    except ValueError:
        number = value.replace(" ", "")  # parts: `cube, cylinder` is the figure `cube,cylinder`
        if op not in ("=", "!="):
            raise ValueError(f"'expect: {name} {op}' needs a number, got {value!r}") from None
    return Condition(name, op, number, line)
