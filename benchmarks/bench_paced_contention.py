"""View benchmark's control: how late paced motion cycles are, with no view at all, when other processes keep the cores busy.

Run: python benchmarks/bench_paced_contention.py [--runs 3]

bench_view's paced pick-and-place run (`--realtime`, no view, no browser) three times each: alone, with as many
busy processes as the machine has cores at nice 0 (what a software-rendering browser on the same machine
amounts to: it takes every core it can get), and with the same processes at nice 10. Printed per case: the
motion cycle's lateness p99 against the wall clock (ms) of each run and their median. It tells whether a view's
lateness figure is the view's doing or the machine's.
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


def lateness_runs(busy: int, nice: int, runs: int, program: Path) -> list[float]:
    """Lateness p99 (ms) of `runs` paced runs while `busy` processes at `nice` spin."""
    spinners = [multiprocessing.Process(target=_spin, args=(nice,), daemon=True) for _ in range(busy)]
    for spinner in spinners:
        spinner.start()
    try:
        return [round(bench_view.p99_ms(bench_view.one_run(program, None, True, "none")), 3) for _ in range(runs)]
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
        for name, busy, nice in (("alone", 0, 0), ("busy", cores, 0), ("busy_nice10", cores, 10)):
            runs = lateness_runs(busy, nice, args.runs, program)
            print(f"lateness_p99_ms_{name}_runs={','.join(f'{r:g}' for r in runs)}")
            print(f"lateness_p99_ms_{name}={statistics.median(runs):g}", flush=True)


if __name__ == "__main__":
    main()
