"""One run in a worker: the `orc run` command itself, called in the worker's process with its output captured."""

from __future__ import annotations

import contextlib
import io
import json
import os
import socket
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

from orc_rpl.plant.clearance import DISTMAX_M, nearest_in_default_cell
from orc_rpl.robot.robots import ROBOTS
from orc_rpl.signals.recording import Recording

#: The `orc` entry point (`orc_rpl.cli.main`), handed down by the command so the worker runs exactly `orc run`.
OrcMain = Callable[[list[str]], int]

#: Captured output kept per run (the end of it: the summary and any error are at the end).
OUTPUT_KEPT_CHARS = 4000


@dataclass(frozen=True, slots=True)
class RunSpec:
    """One `orc run`: the program (absolute path: workers see the same files), robot, world and further options."""

    program: str
    robot: str
    world: str | None = None
    settings: tuple[str, ...] = ()          #: `--set NAME=VALUE` overrides of top-level CONSTs
    options: tuple[str, ...] = ()           #: further `orc run` options, already checked against its parser
    record: bool = True                     #: record the joints (for the joint-limit margin)

    def argv(self, summary_json: str, log_npz: str | None) -> list[str]:
        """The command line of this run (after `orc`)."""
        argv = ["run", self.program, "--robot", self.robot, "--summary-json", summary_json]
        if self.world is not None:
            argv += ["--world", self.world]
        for setting in self.settings:
            argv += ["--set", setting]
        if log_npz is not None:
            argv += ["--log", log_npz]
        return argv + list(self.options)


@dataclass(frozen=True, slots=True)
class RunOutcome:
    """What one run gave: its exit code, its JSON summary (None when it never ran), output and joint margin."""

    exit_code: int
    summary: dict[str, Any] | None
    stdout: str
    stderr: str
    joint_margin_deg: float | None = None   #: smallest distance of any joint to its limit over the run
    margin_joint: int | None = None         #: the joint (1-based) where that margin was smallest
    clearance_m: float | None = None        #: nearest approach of the robot's links to the cell's fixed objects
    nearest: str = ""                       #: which link came nearest to which object, and when
    wall_s: float = 0.0
    worker: str = field(default="")         #: host and process id that ran it


def margins(log_npz: Path, robot: str) -> tuple[tuple[float, int] | None, Any]:
    """From the run's recording: the smallest distance (deg) of a joint to its limit and the joint (1-based), and the
    nearest approach to the cell (plant.clearance, sampled at its replay rate); (None, None) without a recording."""
    if not log_npz.is_file() or robot not in ROBOTS:
        return None, None
    recording = Recording.from_npz(log_npz)
    if "q" not in recording.signals or len(recording.time_s) == 0:
        return None, None
    spec = ROBOTS.get(robot)
    q = np.asarray(recording.signals["q"], dtype=float)
    n = min(q.shape[1], len(spec.q_min_rad))
    lower = q[:, :n] - np.asarray(spec.q_min_rad[:n])
    upper = np.asarray(spec.q_max_rad[:n]) - q[:, :n]
    per_joint = np.minimum(lower.min(axis=0), upper.min(axis=0))
    joint = int(np.argmin(per_joint))
    return (float(np.degrees(per_joint[joint])), joint + 1), nearest_in_default_cell(robot, recording.time_s, q)


def _tail(text: str) -> str:
    return text if len(text) <= OUTPUT_KEPT_CHARS else "..." + text[-OUTPUT_KEPT_CHARS:]


def run_task(orc_main: OrcMain, spec: RunSpec) -> RunOutcome:
    """Run `orc run` for `spec` in this process (one thread per worker, so capturing standard output is safe)."""
    out, err = io.StringIO(), io.StringIO()
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="orc-verify-") as scratch:
        summary_json = Path(scratch) / "summary.json"
        log_npz = Path(scratch) / "log.npz" if spec.record else None
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                code = orc_main(spec.argv(str(summary_json), str(log_npz) if log_npz else None))
            except SystemExit as exit_:  # argparse's usage errors
                code = exit_.code if isinstance(exit_.code, int) else 2
            except Exception as error:  # a bug of ours: reported as the run's outcome, never lost
                err.write(f"orc run: internal error (a bug in orc_rpl, please report it): {type(error).__name__}: {error}\n")
                code = 1
        summary = json.loads(summary_json.read_text(encoding="utf-8")) if summary_json.is_file() else None
        margin, approach = margins(log_npz, spec.robot) if log_npz is not None and summary is not None else (None, None)
    return RunOutcome(
        exit_code=code, summary=summary, stdout=_tail(out.getvalue()), stderr=_tail(err.getvalue()),
        joint_margin_deg=None if margin is None else round(margin[0], 6),
        margin_joint=None if margin is None else margin[1],
        clearance_m=None if approach is None else round(approach.distance_m, 6),
        nearest=(f"nothing within {1000 * DISTMAX_M:.0f} mm" if approach is None else
                 f"{approach.robot_geom} to {approach.obstacle_geom} at {approach.time_s:.2f} s") if margin else "",
        wall_s=time.perf_counter() - start, worker=f"{socket.gethostname()}:{os.getpid()}")
