"""Helpers of the verify tests: programs run alone (the reference) and `orc` in a subprocess."""

from __future__ import annotations

import contextlib
import json
import os
import socket
import subprocess
import sys
from pathlib import Path
from typing import Any, Callable, Iterator

import pytest

from orc_rpl.cli import main

ROOT = Path(__file__).resolve().parents[2]

#: A small, fast subset of programs/: both syntaxes, a via motion, a calibration (each under a few seconds).
SUBSET = ("programs/online/thesis_2_4_calibrate.rpl", "programs/online/thesis_4_1_move_via.rpl",
          "programs/offline/thesis_7_3.orl")

UNREACHABLE = ("-- Out of reach on purpose.\n-- expect: Unreachable\nTOOL probe = POSE(0, 0, 100mm, 0, 0, 0)\n"
               "MOVE probe TO POSE(2500mm, 0, 600mm, 0, 180deg, 0)\n")
NOT_AS_EXPECTED = ("-- expect: Unreachable\nTOOL probe = POSE(0, 0, 100mm, 0, 0, 0)\n"
                   "MOVE probe TO POSE(900mm, 0, 700mm, 0, 180deg, 0)\n")
UR5E_ONLY = "-- robots: ur5e\nPRINT 1\n"
COLLIDES = ("-- Into the table (top at 350 mm) on purpose.\nTOOL probe = POSE(0, 0, 100mm, 0, 0, 0)\n"
            "MOVE probe TO POSE(1000mm, 0, 600mm, 0, 180deg, 0)\n"
            "LMOVE probe TO POSE(1000mm, 0, 250mm, 0, 180deg, 0) WITH SPEED = 0.5mps\n")


def alone(program: str | Path, robot: str = "irb2400", margins: bool = False) -> dict[str, Any]:
    """The summary of `orc run PROGRAM` (with `--margins` if asked) run on its own (in this process), with its exit
    code."""
    out = Path(os.environ.get("PYTEST_TMP", "/tmp")) / f"alone-{os.getpid()}.json"
    code = main(["run", str(program), "--robot", robot, "--summary-json", str(out), *(["--margins"] if margins else [])])
    summary = json.loads(out.read_text())
    out.unlink()
    return {**summary, "exit_code": code}


def orc(*argv: str, cwd: Path = ROOT, timeout_s: float = 600) -> subprocess.CompletedProcess[str]:
    """`orc ARGV...` in a subprocess (its own Dask cluster, as a user runs it)."""
    return subprocess.run([sys.executable, "-m", "orc_rpl", *argv], cwd=cwd, capture_output=True, text=True,
                          timeout=timeout_s)


def same_as_alone(row: dict[str, Any], summary: dict[str, Any]) -> None:
    """A verify row shows exactly what the program gave when run alone."""
    error = summary["error"] or {}
    assert (row["status"], row["exception"], row["cycle_time_s"], row["motions"], row["warnings"]) == \
        (summary["status"], error.get("exception"), summary["cycle_time_s"], summary["motions"],
         len(summary["warnings"])), row["program"]


@contextlib.contextmanager
def dask_cluster(folder: Path, workers: int, protocol: str = "tcp",
                 tls: Callable[[str], list[str]] = lambda role: []) -> Iterator[str]:
    """A Dask scheduler and single-threaded workers, each its own process, on 127.0.0.1; yields the address.

    The scheduler gives up on a task at its first worker death, as docs/verify.md advises.
    """
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    env = {**os.environ, "DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES": "0"}
    address = f"{protocol}://127.0.0.1:{port}"
    quiet = {"cwd": folder, "env": env, "stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
    processes = [subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--protocol", protocol,
                                   "--host", "127.0.0.1", "--port", str(port), "--no-dashboard", *tls("scheduler")],
                                  **quiet)]
    try:
        for _ in range(workers):
            processes.append(subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", address, "--host",
                                               "127.0.0.1", "--nthreads", "1", "--no-dashboard", *tls("worker")],
                                              **quiet))
        yield address
    finally:
        for process in reversed(processes):
            process.terminate()
        for process in processes:
            process.wait(timeout=30)


@pytest.fixture
def extra_programs(tmp_path: Path) -> dict[str, Path]:
    files = {"unreachable.rpl": UNREACHABLE, "not_as_expected.rpl": NOT_AS_EXPECTED, "ur5e_only.rpl": UR5E_ONLY,
             "collides.rpl": COLLIDES}
    for name, text in files.items():
        (tmp_path / name).write_text(text, encoding="utf-8")
    return {name: tmp_path / name for name in files}
