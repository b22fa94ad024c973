"""View benchmark's control: how late paced motion cycles are, with no view at all, when other processes keep the cores busy.

Run: python benchmarks/bench_paced_contention.py [--runs 3]

bench_view's paced pick-and-place run (`--realtime`, no view, no browser) three times each: alone, with as many
busy processes as the machine has cores at nice 0 (what a software-rendering browser on the same machine
amounts to: it takes every core it can get), and with the same processes at nice 10, with the motion cycle at normal
priority; then alone and busy again with the motion cycle at real-time priority, as `orc run` asks for it
(`..._realtime`), and once more with the plan-ahead worker left at normal priority, as before
(`..._helpers_normal`: the cycle then waits for the interpreter lock a preempted worker holds). Printed per case: the
motion cycle's lateness p99 against the wall clock (ms) of each run and their
median. It tells whether a view's lateness figure is the view's doing or the machine's, and what the priority does.
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import statistics
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import bench_view  # noqa: E402  (the paced run and its lateness probe live there)


def _spin(nice: int) -> None:
    os.nice(nice)
    while True:
        pass


def lateness_runs(busy: int, nice: int, runs: int, program: Path, realtime: bool, helpers: bool = True) -> list[float]:
    """Lateness p99 (ms) of `runs` paced runs while `busy` processes at `nice` spin; the motion cycle at real-time
    priority (as `orc run` asks for it) or at normal priority."""
    spinners = [multiprocessing.Process(target=_spin, args=(nice,), daemon=True) for _ in range(busy)]
    for spinner in spinners:
        spinner.start()
    try:
        results = [bench_view.one_run(program, None, True, "none", realtime=realtime, helpers=helpers)
                   for _ in range(runs)]
        if realtime and not all(r["realtime"] for r in results):
            print("realtime_refused=1  (the system refused real-time priority: these runs are at normal priority)")
        return [round(bench_view.p99_ms(r), 3) for r in results]
    finally:
        for spinner in spinners:
            spinner.terminate()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    cores = os.cpu_count() or 1
    print(f"cores={cores}")
    print(f"load_average_1min={os.getloadavg()[0]:.2f}")
    with tempfile.TemporaryDirectory() as folder:
        program = bench_view._program(Path(folder), 3)
        for name, busy, nice, realtime, helpers in (
                ("alone", 0, 0, False, True), ("busy", cores, 0, False, True), ("busy_nice10", cores, 10, False, True),
                ("alone_realtime", 0, 0, True, True), ("busy_realtime", cores, 0, True, True),
                ("busy_realtime_helpers_normal", cores, 0, True, False)):
            runs = lateness_runs(busy, nice, args.runs, program, realtime, helpers)
            print(f"lateness_p99_ms_{name}_runs={','.join(f'{r:g}' for r in runs)}")
            print(f"lateness_p99_ms_{name}={statistics.median(runs):g}", flush=True)


if __name__ == "__main__":
    main()
