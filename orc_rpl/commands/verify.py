"""`orc verify [PATHS...]`: run every program found on the simulated cell, in parallel on a Dask cluster, and judge it."""

from __future__ import annotations

import argparse
import sys
import time
from typing import Any

from orc_rpl.commands.many_runs import add_cluster_options, check_output, cluster_settings, run_args
from orc_rpl.errors import OrcError, UsageError
from orc_rpl.robot.robots import ROBOTS
from orc_rpl.verify.judge import FAIL, Row, Thresholds, cancelled, judge, load_baseline, skipped
from orc_rpl.verify.programs import Found, find_programs
from orc_rpl.verify.task import RunSpec

DEFAULT_ROBOT = "irb2400"  # orc run's default
TABLE_WIDTH_OFF_TERMINAL = 200


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    parser = subparsers.add_parser(
        "verify", help="run every program found, in parallel, and judge the results",
        description="Run every .rpl and .orl program found under PATHS on the simulated cell, each exactly as "
                    "`orc run` runs it, on a Dask cluster (a local one on 127.0.0.1 by default), and print a table. "
                    "A program's header comments may say what it must do: `-- expect: Unreachable`, "
                    "`-- robots: irb2400, ur5e`, `-- expect: welds_good = 4`. Exit 1 when a program does other "
                    "than expected, collides, runs slower than its baseline by more than the threshold or its "
                    "process outcomes are worse; 2 on usage errors; 130 when interrupted.")
    parser.add_argument("paths", nargs="*", metavar="PATHS", default=["."], help="program files or folders (default .)")
    parser.add_argument("--world", metavar="FILE|DIR", help="the world of every run (orc run --world)")
    parser.add_argument("--robot", metavar="NAME", nargs="+", action="extend",
                        help="robots to run each program on (default: those of its header, else irb2400)")
    parser.add_argument("--baseline", metavar="FILE", help="compare cycle times with a saved baseline")
    parser.add_argument("--save-baseline", metavar="FILE", help="save this verification's cycle times as a baseline")
    parser.add_argument("--slowdown", metavar="PERCENT", type=float, default=5.0,
                        help="fail a run slower than its baseline by more than this (default 5)")
    parser.add_argument("--min-clearance", metavar="MM", type=float, default=0.0,
                        help="fail a run whose robot comes nearer than this to the cell's objects (default 0: "
                             "only collisions fail)")
    parser.add_argument("--clearance-drop", metavar="MM", type=float,
                        help="fail a run whose clearance shrank by more than this against the baseline (default: "
                             "the change is shown, not failed)")
    parser.add_argument("--process-tolerance", metavar="PERCENT", type=float, default=5.0,
                        help="fail a run whose process figures (burr left, seam error...) are worse than the "
                             "baseline's by more than this; counts and parts must match (default 5)")
    parser.add_argument("--junit", metavar="FILE", help="write JUnit XML for CI systems")
    parser.add_argument("--json", metavar="FILE", help="write every row as JSON")
    add_cluster_options(parser)
    return parser


def plan(found: list[Found], robots: list[str] | None) -> list[tuple[Found, str]]:
    """Every (program, robot) pair to consider, in a stable order."""
    for name in robots or []:
        if name not in ROBOTS:
            raise UsageError(f"--robot: unknown robot {name!r}; known robots: {', '.join(ROBOTS.names())}")
    pairs = []
    for program in found:
        for name in program.expectation.robots:
            if name not in ROBOTS:
                raise UsageError(f"{program.shown}: 'robots:' names an unknown robot {name!r}; "
                                 f"known robots: {', '.join(ROBOTS.names())}")
        chosen = robots or list(program.expectation.robots) or [DEFAULT_ROBOT]
        pairs.extend((program, name) for name in chosen)
    return pairs


def run(args: argparse.Namespace) -> int:
    try:
        found = find_programs(args.paths)
        if not found:
            raise UsageError(f"no .rpl or .orl programs under {', '.join(args.paths)}")
        pairs = plan(found, args.robot)
        options = run_args(args.run_args)
        baseline = load_baseline(args.baseline) if args.baseline else {}
        for option, path in (("--junit", args.junit), ("--json", args.json), ("--save-baseline", args.save_baseline)):
            check_output(option, path)
        settings = cluster_settings(args)
        from orc_rpl.verify.engine import Engine

        engine = Engine(settings)
    except UsageError as error:
        sys.stderr.write(f"orc verify: error: {error}\n")
        return 2
    try:
        return _verify(args, engine, pairs, options, baseline)
    except OrcError as error:
        sys.stderr.write(f"orc verify: error: {error}\n")
        return 1


def _verify(args: argparse.Namespace, engine: Any, pairs: list[tuple[Found, str]], options: tuple[str, ...],
            baseline: dict[str, Any]) -> int:
    from rich.console import Console

    from orc_rpl.verify import reports
    from orc_rpl.verify.table import StreamingTable, build_table
    from orc_rpl.verify.task import run_task

    rows: dict[int, Row] = {}
    to_run: list[int] = []
    for index, (program, robot) in enumerate(pairs):
        if program.expectation.robots and robot not in program.expectation.robots:
            rows[index] = skipped(program.shown, robot, program.expectation)
        else:
            to_run.append(index)
    specs = [RunSpec(str(pairs[i][0].path), pairs[i][1], args.world, options=options) for i in to_run]
    # Off a terminal (CI logs, files) the table keeps its full width instead of wrapping at 80 columns.
    out = Console(file=sys.stdout, width=None if sys.stdout.isatty() else TABLE_WIDTH_OFF_TERMINAL)
    status = Console(file=sys.stderr, soft_wrap=True)
    interrupted = False
    limits = Thresholds(args.slowdown, args.min_clearance, args.clearance_drop, args.process_tolerance)
    wall_start = time.perf_counter()
    with engine, StreamingTable(len(specs), bool(baseline), out, status) as table:
        try:
            for done in engine.results(run_task, specs, args.orc_main):
                index = to_run[done.index]
                program, robot = pairs[index]
                rows[index] = judge(program.shown, robot, program.expectation, done.result, done.attempts,
                                    done.failure, baseline, limits)
                table.add(rows[index])
        except KeyboardInterrupt:
            interrupted = True
    wall_s = time.perf_counter() - wall_start
    for index, (program, robot) in enumerate(pairs):
        if index not in rows:
            rows[index] = cancelled(program.shown, robot, program.expectation)
    ordered = [rows[i] for i in range(len(pairs))]
    out.print(build_table(ordered, bool(baseline)))
    tally = reports.counts(ordered)
    status.print(f"{tally['runs']} runs: {tally['ok']} ok, {tally['failed']} failed, {tally['skipped']} skipped, "
                 f"{tally['cancelled']} cancelled ({wall_s:.1f} s wall)", markup=False, highlight=False)
    if args.json:
        reports.write_json(args.json, ordered, {"scheduler": args.scheduler or "local", "slowdown_pct": args.slowdown,
                                               "min_clearance_mm": args.min_clearance,
                                               "clearance_drop_mm": args.clearance_drop,
                                               "process_tolerance_pct": args.process_tolerance,
                                               "wall_s": round(wall_s, 3)})
    if args.junit:
        reports.write_junit(args.junit, ordered, wall_s)
    if args.save_baseline:
        reports.write_baseline(args.save_baseline, ordered)
    if interrupted:
        status.print("orc verify: interrupted: the remaining runs were cancelled; the finished ones are kept above",
                     markup=False, highlight=False)
        return 130
    return 1 if any(row.verdict == FAIL for row in ordered) else 0
