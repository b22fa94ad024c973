"""The rich table of `orc verify`: rows stream in as runs finish, under a progress bar with ETA."""

from __future__ import annotations

from typing import Any

from rich.console import Console, Group
from rich.live import Live
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn
from rich.table import Table

from orc_rpl.verify.judge import CANCELLED, FAIL, OK, SKIPPED, Row

_STYLE = {OK: "green", FAIL: "bold red", SKIPPED: "dim", CANCELLED: "yellow"}


def _process_text(process: Any) -> str:
    """A process section in one short cell: scalars as name=value, lists of records as their count (how many are
    good, how many faults were not caught, when the records say so)."""
    if process is None:
        return ""
    if not isinstance(process, dict):
        return str(process)[:40]
    items = []
    for name, value in process.items():
        if isinstance(value, float):
            items.append(f"{name}={value:.4g}")
        elif isinstance(value, (int, str, bool)):
            items.append(f"{name}={value}")
        elif isinstance(value, dict):
            items.append(f"{name}: {_process_text(value)}")
        elif isinstance(value, list) and value:
            records = [r for r in value if isinstance(r, dict)]
            good = sum(1 for r in records if r.get("good") is True)
            uncaught = sum(1 for r in records if r.get("caught") is False)
            items.append(f"{name} {len(value)}" + (f" ({good} good)" if any("good" in r for r in records) else "")
                         + (f" ({uncaught} not caught)" if uncaught else ""))
    text = ", ".join(items)
    return text if len(text) <= 60 else text[:57] + "..."


def _clearance(row: Row) -> str:
    """The nearest approach, the line of its motion and its change against the baseline."""
    if row.clearance_mm is None:
        return "> 500 mm" if row.measured else ""
    text = f"{row.clearance_mm:.0f} mm" + (f" @{row.clearance_at.rpartition(':')[2]}" if row.clearance_at else "")
    if row.baseline_clearance_mm is not None and round(row.clearance_mm - row.baseline_clearance_mm) != 0:
        text += f" ({row.clearance_mm - row.baseline_clearance_mm:+.0f})"
    return f"[bold red]{text} COLLISION[/]" if row.clearance_mm < 0 else text


def _margin(row: Row) -> str:
    if row.joint_margin_deg is None:
        return ""
    return f"{row.joint_margin_deg:.1f} deg j{row.margin_joint} @{row.margin_at.rpartition(':')[2]}"


def _change(row: Row, have_baseline: bool) -> str:
    if row.change_pct is not None:
        return f"{row.change_pct:+.1f} %"
    return "new" if have_baseline and row.cycle_time_s is not None else ""


def build_table(rows: list[Row], have_baseline: bool) -> Table:
    """The table of these rows; the process column only when a run reported a process section."""
    with_process = any(row.process is not None for row in rows)
    table = Table(title="orc verify", title_justify="left")
    for name, justify in (("program", "left"), ("robot", "left"), ("status", "left"), ("cycle s", "right"),
                          ("vs baseline", "right"), ("motions", "right"), ("clearance", "right"),
                          ("joint margin", "right")):
        # a program's path is what the reader searches for: never wrapped (the other columns fold first)
        table.add_column(name, justify=justify, no_wrap=name == "program")  # type: ignore[arg-type]
    if with_process:
        table.add_column("process")
    table.add_column("warnings", justify="right")
    table.add_column("verdict")
    for row in rows:
        status = row.status + (f" ({row.exception})" if row.exception else "")
        if row.attempts > 1:
            status += f", retried {row.attempts - 1}x"
        cells = [row.program, row.robot, status,
                 "" if row.cycle_time_s is None else f"{row.cycle_time_s:.3f}",
                 _change(row, have_baseline),
                 "" if row.motions is None else str(row.motions),
                 _clearance(row),
                 _margin(row)]
        if with_process:
            cells.append(_process_text(row.process))
        verdict = row.verdict + (": " + "; ".join(row.reasons) if row.reasons else "")
        cells += [str(row.warnings) if row.warnings else "", f"[{_STYLE[row.verdict]}]{verdict}[/]"]
        table.add_row(*cells)
    return table


class StreamingTable:
    """Rows as they finish with a progress bar on a terminal; one line per finished run elsewhere (CI logs)."""

    def __init__(self, total: int, have_baseline: bool, console: Console, status: Console) -> None:
        self.rows: list[Row] = []
        self.total, self.have_baseline, self.console, self.status = total, have_baseline, console, status
        self.progress = Progress(TextColumn("runs"), BarColumn(), MofNCompleteColumn(), TextColumn("ETA"),
                                 TimeRemainingColumn(), TimeElapsedColumn(), console=status)
        self._task = self.progress.add_task("runs", total=total)
        self._live: Live | None = None

    def __enter__(self) -> StreamingTable:
        if self.status.is_terminal:
            self._live = Live(self._view(), console=self.status, transient=True, refresh_per_second=4,
                              vertical_overflow="visible")
            self._live.__enter__()
        return self

    def _view(self) -> Group:
        return Group(build_table(self.rows[-20:], self.have_baseline), self.progress)  # the latest rows, then the bar

    def add(self, row: Row) -> None:
        self.rows.append(row)
        self.progress.advance(self._task)
        if self._live is not None:
            self._live.update(self._view())
        else:
            reasons = f" ({'; '.join(row.reasons)})" if row.reasons else ""
            cycle = "" if row.cycle_time_s is None else f" {row.cycle_time_s:.3f} s"
            self.status.print(f"[{len(self.rows)}/{self.total}] {row.verdict} {row.program} {row.robot} "
                              f"{row.status}{cycle}{reasons}", markup=False, highlight=False)

    def __exit__(self, *exc: Any) -> None:
        if self._live is not None:
            self._live.__exit__(*exc)
