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
    margins: bool = True                    #: measure clearance and joint margins per motion (orc run --margins)

    def argv(self, summary_json: str) -> list[str]:
        """The command line of this run (after `orc`)."""
        argv = ["run", self.program, "--robot", self.robot, "--summary-json", summary_json]
        if self.world is not None:
            argv += ["--world", self.world]
        for setting in self.settings:
            argv += ["--set", setting]
        if self.margins:
            argv.append("--margins")
        return argv + list(self.options)


@dataclass(frozen=True, slots=True)
class RunOutcome:
    """What one run gave: its exit code, its JSON summary (None when it never ran; its `margins` section has the
    clearance and joint margins per motion) and its output."""

    exit_code: int
    summary: dict[str, Any] | None
    stdout: str
    stderr: str
    wall_s: float = 0.0
    worker: str = field(default="")         #: host and process id that ran it


def _tail(text: str) -> str:
    return text if len(text) <= OUTPUT_KEPT_CHARS else "..." + text[-OUTPUT_KEPT_CHARS:]


def run_task(orc_main: OrcMain, spec: RunSpec) -> RunOutcome:
    """Run `orc run` for `spec` in this process (one thread per worker, so capturing standard output is safe)."""
    out, err = io.StringIO(), io.StringIO()
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="orc-verify-") as scratch:
        summary_json = Path(scratch) / "summary.json"
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                code = orc_main(spec.argv(str(summary_json)))
            except SystemExit as exit_:  # argparse's usage errors
                code = exit_.code if isinstance(exit_.code, int) else 2
            except Exception as error:  # a bug of ours: reported as the run's outcome, never lost
                err.write(f"orc run: internal error (a bug in orc_rpl, please report it): {type(error).__name__}: {error}\n")
                code = 1
        summary = json.loads(summary_json.read_text(encoding="utf-8")) if summary_json.is_file() else None
    return RunOutcome(
        exit_code=code, summary=summary, stdout=_tail(out.getvalue()), stderr=_tail(err.getvalue()),
        wall_s=time.perf_counter() - start, worker=f"{socket.gethostname()}:{os.getpid()}")
