"""Verify benchmark: parallel efficiency of 2 worker processes over 8 equal short programs, and the overhead per run.

Run: python benchmarks/bench_verify.py [--programs 8] [--laps 20] [--repeats 3]
The last lines are `key=value` figures (targets: parallel_efficiency >= 0.8 with 2 workers on a quiet machine with at
least 2 free cores; scheduling_overhead_ms < 50), and what measuring the margins (orc run --margins: clearance and joint
margins per motion) costs one run of the corpus program. BLAS and OpenMP threads are pinned to 1 here and in the workers.
"""

from __future__ import annotations

import os

for _name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_name] = "1"  # before numpy is imported, here and (inherited) in the workers

import argparse  # noqa: E402
import math  # noqa: E402
import statistics  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

from bench_executive import MOTIONS  # noqa: E402  (benchmarks/ is the script's folder)
from orc_rpl.cli import main  # noqa: E402
from orc_rpl.verify.engine import ClusterSettings, Engine  # noqa: E402
from orc_rpl.verify.task import RunSpec, run_task  # noqa: E402

#: One short program: laps of a blended rectangle in front of the robot (every copy is the same work); the
#: executive benchmark's 1,000-motion program, shortened.
PROGRAM = MOTIONS

#: The projection printed at the end: a plant's programs on a cluster of nodes with this many workers each.
PROJECTION_RUNS, PROJECTION_NODES, PROJECTION_WORKERS_PER_NODE = 1000, 100, 2


def _warm(program: str) -> int:
    """Run one program in this worker so that imports and caches are paid before the timed batch."""
    return run_task(main, RunSpec(program, "irb2400")).exit_code


def batch(workers: int, specs: list[RunSpec]) -> tuple[float, list[float], float]:
    """Wall time of the batch on a fresh warm local cluster, the runs' own times, and the cluster's start time."""
    start = time.perf_counter()
    with Engine(ClusterSettings(workers=workers)) as engine:
        engine.client.wait_for_workers(workers)
        codes = engine.client.run(_warm, specs[0].program)
        started_s = time.perf_counter() - start
        assert set(codes.values()) == {0}, codes
        begin = time.perf_counter()
        done = list(engine.results(run_task, specs, main))
        wall_s = time.perf_counter() - begin
    assert all(d.result is not None and d.result.exit_code == 0 and d.attempts == 1 for d in done), done
    return wall_s, [d.result.wall_s for d in done], started_s


def margins_cost(program: str, repeats: int) -> tuple[float, float, float, int, int]:
    """One program in this process with and without `orc run --margins`, alternately: the median wall times (s), the
    simulated cycle (s), and how many motion cycles were sampled and how many of them measured exactly."""
    off, on = [], []
    for _ in range(repeats):
        off.append(run_task(main, RunSpec(program, "irb2400", margins=False)).wall_s)
        measured = run_task(main, RunSpec(program, "irb2400", margins=True))
        on.append(measured.wall_s)
    assert measured.summary is not None, measured.stderr
    section = measured.summary["margins"]
    return (statistics.median(off), statistics.median(on), measured.summary["cycle_time_s"], section["samples"],
            section["measured"])


def main_bench() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--programs", type=int, default=8)
    parser.add_argument("--laps", type=int, default=20)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="bench-verify-") as folder:
        specs = []
        for i in range(args.programs):
            path = Path(folder) / f"corpus_{i}.rpl"
            path.write_text(PROGRAM.format(laps=args.laps), encoding="utf-8")
            specs.append(RunSpec(str(path), "irb2400"))
        _warm(specs[0].program)
        wall_off, wall_on, cycle_s, samples, measured = margins_cost(specs[0].program, args.repeats)
        one, two, overheads, per_run, starts = [], [], [], [], []
        for _ in range(args.repeats):
            wall_1, runs_1, start_1 = batch(1, specs)
            wall_2, _, start_2 = batch(2, specs)
            one.append(wall_1)
            two.append(wall_2)
            # On one worker the runs follow each other: what the batch took beyond the runs themselves is the
            # scheduling, serialisation and result transport of each run.
            overheads.append((wall_1 - sum(runs_1)) / len(specs))
            per_run.extend(runs_1)
            starts.extend((start_1, start_2))
    wall_1, wall_2 = statistics.median(one), statistics.median(two)
    speedup = wall_1 / wall_2
    efficiency = speedup / 2
    overhead_s = statistics.median(overheads)
    run_s = statistics.median(per_run)
    workers = PROJECTION_NODES * PROJECTION_WORKERS_PER_NODE
    rounds = math.ceil(PROJECTION_RUNS / workers)
    # Runs spread over the workers in rounds, each round as slow as one run plus its overhead; the measured efficiency
    # stands for what two workers per node lose to each other. The overhead is measured end to end; were all of it
    # spent in the one scheduler, one run after another, the batch could not take less than runs x overhead.
    projected_s = rounds * (run_s + overhead_s) / efficiency
    scheduler_serial_s = PROJECTION_RUNS * overhead_s
    print(f"cpu_count={os.cpu_count()} load_1min={os.getloadavg()[0]:.2f}")
    print(f"programs={len(specs)} laps={args.laps} repeats={args.repeats}")
    print(f"wall_1_worker_s={wall_1:.3f} wall_2_workers_s={wall_2:.3f}")
    print(f"cluster_start_s={statistics.median(starts):.2f}")
    print(f"per_run_s={run_s:.3f}")
    print(f"speedup_2_workers={speedup:.3f}")
    print(f"parallel_efficiency={efficiency:.3f} target=0.8 {'ok' if efficiency >= 0.8 else 'BELOW TARGET'}")
    print(f"scheduling_overhead_ms={1000 * overhead_s:.1f} target=50 {'ok' if overhead_s < 0.05 else 'ABOVE TARGET'}")
    print(f"margins_cycle_s={cycle_s:.3f} margins_samples={samples} margins_measured={measured} "
          f"margins_rate_hz={samples / cycle_s:.0f}")
    print(f"run_wall_s={wall_off:.3f} run_with_margins_wall_s={wall_on:.3f} "
          f"margins_cost_pct={100 * (wall_on - wall_off) / wall_off:.1f}")
    print(f"projection_runs={PROJECTION_RUNS} projection_nodes={PROJECTION_NODES} "
          f"projection_workers_per_node={PROJECTION_WORKERS_PER_NODE} projected_wall_s={projected_s:.1f} "
          f"projected_scheduler_serial_bound_s={scheduler_serial_s:.1f} "
          f"projected_one_worker_s={PROJECTION_RUNS * (run_s + overhead_s):.1f}")


if __name__ == "__main__":
    main_bench()
