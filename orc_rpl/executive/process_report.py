"""What a run reports of its processes: the summary's `process` section, its lines on standard error, the recorded process signals."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from orc_rpl.application.process_log import SIGNALS, ProcessLog, process_log

#: Units of the signals `orc run --log` records, for the plot's axes.
SIGNAL_UNITS: dict[str, str] = {
    "q_ref": "rad", "q": "rad", "tau": "N m", "s": "path coordinate, 1", "tcp": "m", "tool_tcp": "m",
    **{f"process.{name}": unit for name, unit in SIGNALS.items()},
}


def submit_process_signals(logger: Any, robot: Any, tool: Any) -> ProcessLog:
    """Make the run's process record (on the robot itself, before any wrapper sees it) and, with a logger,
    record the TCP of the tool last moved (`tool_tcp`, world, m) and the process signals (`process.<name>`)
    beside the flange's `tcp`; `tool()` gives the tool's pose."""
    log = process_log(robot)
    if logger is None:
        return log

    def tool_tcp() -> np.ndarray:
        pose = robot.tcp_pose(tool())
        return np.array((pose.x, pose.y, pose.z))
    logger.submit("tool_tcp", tool_tcp)
    for name in SIGNALS:
        logger.submit(f"process.{name}", lambda name=name: log.signals[name])
    return log


def process_section(robot: Any, error: Any) -> dict[str, Any] | None:
    """The summary's `process` section (None when no process ran); each fault says whether the program caught it."""
    log = getattr(robot, "process_log", None)
    if not log:
        return None
    section = log.as_dict()
    uncaught = (error.name, error.message) if error is not None else None
    for fault in section["faults"]:
        fault["caught"] = uncaught is None or fault["exception"] != uncaught[0] or fault["message"] not in uncaught[1]
    return section


def uncaught_warnings(section: dict[str, Any] | None) -> list[str]:
    """A warning for each process fault the program did not catch."""
    if section is None:
        return []
    return [f"process fault not caught: {f['exception']}: {f['message']}" for f in section["faults"] if not f["caught"]]


def process_lines(section: dict[str, Any] | None) -> list[str]:
    """The process outcomes in a few words each, for the human summary."""
    if section is None:
        return []
    lines = []
    welds = section["welds"]
    if welds:
        good = [w for w in welds if w["good"]]
        worst_speed = max(w["speed_m_s"] for w in welds)
        worst_offset = max(w["offset_m"] for w in welds)
        lines.append(f"welds: {len(good)} good of {len(welds)}; at closing the TCP moved at most "
                     f"{1000 * worst_speed:.1f} mm/s and was at most {1000 * worst_offset:.2f} mm off its spot")
        lines += [f"  bad weld at t = {w['time_s']:.3f} s: {w['reason']}" for w in welds if not w["good"]]
    for b in section["bulges"]:
        passes = len(b["pass_heights_m"])
        lines.append(f"bulge {1000 * b['caught_height_m']:.2f} mm caught at s = {b['s0']:.2f}..{b['s1']:.2f}, "
                     f"ground to {round(1000 * b['left_m'], 2) + 0.0:.2f} mm in {passes} pass{'es' if passes != 1 else ''}"
                     + ("" if b["within_tolerance"] else " (above the tolerance)"))
    for s in section["seams"]:
        lines.append(f"seam tracked over {1000 * s['length_m']:.0f} mm: the laser's error {1000 * s['rms_m']:.2f} mm RMS, "
                     f"{1000 * s['max_m']:.2f} mm max (gain {s['gain']:.3f})")
    for i in section["identifications"]:
        answer = i["part"] or "uncertain"
        lines.append(f"part identified: {answer}, payload {i['payload_kg']:.3f} kg +- {i['sigma_kg']:.3f} kg, "
                     f"confidence {100 * i['confidence']:.1f} %")
    for t in section["tunings"]:
        lines.append(f"{t['label']} from {t['samples']} samples" if "label" in t
                     else "tuning: " + ", ".join(f"{k} {_short(v)}" for k, v in t.items()))
    for f in section["faults"]:
        lines.append(f"{f['exception']} at t = {f['time_s']:.3f} s ({'caught' if f['caught'] else 'not caught'}): "
                     f"{f['message']}")
    return lines


def _short(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:.4g}" if math.isfinite(value) else str(value)
    if isinstance(value, list):
        return "[" + ", ".join(_short(v) for v in value) + "]"
    return str(value)


def plotted_signals(recording: Any) -> list[str]:
    """The signals worth a panel: all but the TCP paths and the process signals that never had a value."""
    return [name for name in recording.names if name not in ("tcp", "tool_tcp")
            and not (name.startswith("process.") and np.all(np.isnan(recording[name])))]
