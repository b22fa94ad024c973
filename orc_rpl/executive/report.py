"""What a run reports: the JSON summary, the summary on standard error, and a rich progress display."""

from __future__ import annotations

from typing import Any, TextIO

from orc_rpl.executive.executive import Executive
from orc_rpl.executive.process_report import process_lines, process_section, uncaught_warnings
from orc_rpl.world.pose import Pose, shown_pose


def summary(executive: Executive, robot: Any) -> dict[str, Any]:
    """Status, cycle time, motions, prints, final TCP pose and the error (with its place and call stack)."""
    tcp = robot.tcp_pose(executive.machine.last_tool)
    result: dict[str, Any] = {
        "status": executive.status,
        "cycle_time_s": round(robot.time_s(), 9),
        "motions": executive.motions,
        "prints": list(executive.prints),
        "final_tcp": {"x_m": tcp.x, "y_m": tcp.y, "z_m": tcp.z, "a_rad": tcp.a, "b_rad": tcp.b, "c_rad": tcp.c},
        "warnings": [{"line": span.line, "column": span.column, "message": message}
                     for span, message in executive.machine.warnings],
        "error": None,
    }
    planning = getattr(robot, "planning", None)
    if planning is not None:  # thesis 5.2: moves planned while the one before runs, and whether the plans held
        result["planning"] = {"planned_ahead": planning.planned_ahead, "reused": planning.reused,
                              "replanned": planning.replanned, "at_start": planning.at_start}
        if planning.from_dummy:  # motions computed from sensor dummies (executive/sensor_ahead.py)
            result["planning"].update(from_dummy=planning.from_dummy, confirmed=planning.confirmed,
                                      corrected=planning.corrected)
    error = executive.error
    if error is not None:
        span = error.span
        result["error"] = {
            "line": span.line if span else 0,
            "column": span.column if span else 0,
            "message": error.message,
            "exception": error.name,
            "call_stack": [{"routine": e.routine, "line": e.line, "column": e.column} for e in error.stack],
        }
    process = process_section(robot, error)
    if process is not None:  # what the processes achieved (welds, bulges, seams, parts, tunings) and their faults
        result["process"] = process
        result["warnings"] += [{"line": result["error"]["line"], "column": result["error"]["column"], "message": message}
                               for message in uncaught_warnings(process)]
    return result


def write_summary_text(result: dict[str, Any], wall_s: float, stream: TextIO, real_arm: bool = False) -> None:
    """The human summary on standard error (`real_arm`: the run moved a real arm, its times are the arm's)."""
    tcp = result["final_tcp"]
    cycle = result["cycle_time_s"]
    ratio = f", {cycle / wall_s:.0f}x real time" if wall_s > 0 and cycle > 0 else ""
    pose = shown_pose(Pose(tcp["x_m"], tcp["y_m"], tcp["z_m"], tcp["a_rad"], tcp["b_rad"], tcp["c_rad"])).text()
    timing = f"on the arm; {wall_s:.2f} s wall" if real_arm else f"simulated; {wall_s:.2f} s wall{ratio}"
    stream.write(f"status: {result['status']}\n"
                 f"cycle time: {cycle:.3f} s ({timing})\n"
                 f"motions: {result['motions']}\n"
                 f"final TCP: {pose}\n")
    planning = result.get("planning")
    if planning is not None:
        stream.write(f"planning: {planning['planned_ahead']} motions planned ahead ({planning['reused']} plans used, "
                     f"{planning['replanned']} made again), {planning['at_start']} planned when they started\n")
        if planning.get("from_dummy"):
            stream.write(f"planning: {planning['from_dummy']} motions computed ahead from sensor dummies, before the "
                         f"sensor answered ({planning['confirmed']} confirmed, {planning['corrected']} corrected by "
                         "its answer)\n")
    for line in process_lines(result.get("process")):
        stream.write(f"process: {line}\n")


class Progress:
    """A one-line rich display on a terminal (time, motions, line), refreshed every `every_ticks` motion cycles of
    `robot` (it listens to them); nothing when standard error is not a terminal."""

    def __init__(self, executive: Executive, stream: TextIO, every_ticks: int, robot: Any) -> None:
        self.executive, self.stream, self.every, self.robot = executive, stream, every_ticks, robot
        self._live: Any = None
        self._ticks = 0

    def __enter__(self) -> Progress:
        if self.stream.isatty():
            from rich.console import Console
            from rich.live import Live

            self._live = Live(self._text(), console=Console(file=self.stream), transient=True, refresh_per_second=8,
                              redirect_stdout=False, redirect_stderr=False)  # PRINT lines stay on standard output
            self._live.__enter__()
            self.robot.tick_listeners.add(self.on_tick)
        return self

    def on_tick(self) -> None:
        self._ticks += 1
        if self._ticks % self.every == 0:
            self.refresh()

    def refresh(self) -> None:
        if self._live is not None:
            self._live.update(self._text())

    def _text(self) -> Any:
        from rich.text import Text

        m = self.executive.machine
        stack = m.stack_entries()
        where = f"in {stack[-1].routine}" if len(stack) > 1 else ""
        return Text(f"running {self.executive.path}: t = {self.robot.time_s():7.2f} s, {m.motions} motions {where}",
                    style="cyan")

    def __exit__(self, *exc: Any) -> None:
        if self._live is not None:
            self.robot.tick_listeners.discard(self.on_tick)
            self._live.__exit__(*exc)
