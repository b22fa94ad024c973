"""`orc sweep PROG --set NAME=V1,V2`: run a program over a grid of CONST values, seeds and plant variations."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

from orc_rpl.commands.many_runs import add_cluster_options, cluster_settings, run_accepts, run_args
from orc_rpl.errors import OrcError, UsageError
from orc_rpl.robot.robots import ROBOTS
from orc_rpl.verify.sweep import Variation, grid, record_of, spec_of, split_values, write_table


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    parser = subparsers.add_parser(
        "sweep", help="run a program over a grid of parameters, in parallel",
        description="Run PROG once per combination of the CONST values given with --set (and of the seeds and "
                    "plant variations, where orc run accepts them), each run exactly as `orc run` runs it, on a "
                    "Dask cluster; write the results as CSV and JSON lines and plot one outcome against a parameter. "
                    "Exit 1 when a run could not be carried out (its worker died twice), 2 on usage errors, "
                    "130 when interrupted (the finished runs are written).")
    parser.add_argument("program", metavar="PROG", help="program file (.rpl, or .orl with its world model)")
    parser.add_argument("--set", metavar="NAME=V1,V2,...", action="append", default=[], dest="sets",
                        help="values of a top-level CONST (repeatable: the grid is every combination)")
    parser.add_argument("--seeds", metavar="N", type=int, help="run every point with seeds 0..N-1 (orc run --seed)")
    parser.add_argument("--plant-variation", metavar="FILE",
                        help="YAML list of named variations, each a set of orc run options (see docs/verify.md)")
    parser.add_argument("--robot", metavar="NAME", default="irb2400", help="robot model (default irb2400)")
    parser.add_argument("--world", metavar="FILE|DIR", help="the world of every run (orc run --world)")
    parser.add_argument("--out", metavar="PREFIX", help="write PREFIX.csv, PREFIX.jsonl and PREFIX.png "
                                                       "(default sweep-<program name>)")
    parser.add_argument("--outcome", metavar="FIELD[,FIELD...]", default="cycle_time_s",
                        help="the columns to plot, a panel each (default cycle_time_s; e.g. motions, clearance_mm, "
                             "joint_margin_deg, figure.*, process.*)")
    parser.add_argument("--x", metavar="NAME", help="the parameter on the plot's x axis: a --set NAME, variation or seed (default: the first --set, else variation, else seed)")
    parser.add_argument("--overwrite", action="store_true", help="replace output files that already exist")
    add_cluster_options(parser)
    return parser


def read_variations(path: str) -> list[Variation]:
    """`variations: [{name: light, run-args: "--plant ideal"}, ...]` with every option checked against orc run."""
    from ruamel.yaml import YAML, YAMLError

    try:
        data = YAML(typ="safe", pure=True).load(Path(path).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, YAMLError) as error:
        raise UsageError(f"--plant-variation: cannot read '{path}': {error}") from None
    items = data.get("variations") if isinstance(data, dict) else None
    if not isinstance(items, list) or not items:
        raise UsageError(f"--plant-variation: '{path}' needs a non-empty list 'variations' "
                         "of {name: ..., run-args: ...}")
    variations = []
    for number, item in enumerate(items, start=1):
        if not isinstance(item, dict) or not isinstance(item.get("name"), str) or \
                not isinstance(item.get("run-args", ""), str):
            raise UsageError(f"--plant-variation: '{path}', variation {number}: expected name: TEXT, run-args: TEXT")
        try:
            options = run_args(item.get("run-args", ""))
        except UsageError as error:
            raise UsageError(f"--plant-variation: '{path}', variation {item['name']!r}: {error}") from None
        variations.append(Variation(item["name"], options))
    if len({v.name for v in variations}) != len(variations):
        raise UsageError(f"--plant-variation: '{path}': two variations have the same name")
    return variations


def run(args: argparse.Namespace) -> int:
    try:
        program = Path(args.program)
        if not program.is_file() or program.suffix not in (".rpl", ".orl"):
            raise UsageError(f"'{args.program}' is not a program file (.rpl or .orl)")
        if not (args.sets or args.seeds is not None or args.plant_variation):
            raise UsageError("give at least one --set NAME=V1,V2,..., --seeds N or --plant-variation FILE")
        if args.robot not in ROBOTS:
            raise UsageError(f"--robot: unknown robot {args.robot!r}; known robots: {', '.join(ROBOTS.names())}")
        if args.seeds is not None:
            if not run_accepts("--seed"):
                raise UsageError("--seeds: orc run of this installation has no --seed option yet")
            if args.seeds < 1:
                raise UsageError(f"--seeds must be at least 1, got {args.seeds}")
        variations = read_variations(args.plant_variation) if args.plant_variation else []
        points = grid(args.sets, args.seeds, variations)
        names = [split_values(text)[0] for text in args.sets]
        # the plot's x axis: a --set parameter, else the variations, else the seeds
        axes = names + (["variation"] if variations else []) + (["seed"] if args.seeds is not None else [])
        x = args.x or axes[0]
        if x not in axes:
            raise UsageError(f"--x: {x!r} is not one of the swept parameters ({', '.join(axes)})")
        prefix = Path(args.out) if args.out else Path(f"sweep-{program.stem}")
        outputs = [prefix.with_name(prefix.name + suffix) for suffix in (".csv", ".jsonl", ".png")]
        if not prefix.resolve().parent.is_dir():
            raise UsageError(f"--out: the folder of '{prefix}' does not exist")
        existing = [str(p) for p in outputs if p.exists()]
        if existing and not args.overwrite:
            raise UsageError(f"{', '.join(existing)} already exist; choose another --out or give --overwrite")
        options = run_args(args.run_args)
        from orc_rpl.verify.engine import Engine

        engine = Engine(cluster_settings(args))
        # The first point runs alone first (in this process): a misspelt CONST or a bad value stops the sweep here.
        _check_first(args, points[0], options)
    except UsageError as error:
        sys.stderr.write(f"orc sweep: error: {error}\n")
        return 2
    try:
        return _sweep(args, engine, points, options, names, x, outputs, str(program.resolve()))
    except OrcError as error:
        sys.stderr.write(f"orc sweep: error: {error}\n")
        return 1


def _check_first(args: argparse.Namespace, point: Any, options: tuple[str, ...]) -> None:
    """Load the program with the first point's values: the same loading and checks `orc run` does, nothing moves."""
    from orc_rpl.transform.loading import load_program
    from orc_rpl.transform.overrides import override_constants
    from orc_rpl.errors import SourceError

    world = args.world if args.world is not None and Path(args.world).is_file() else None
    try:
        _, tree = load_program(args.program, world)
    except SourceError as error:
        raise UsageError(error.format()) from None
    except OrcError as error:  # an off-line program its world model cannot map
        raise UsageError(str(error)) from None
    override_constants(tree, [f"{name}={value}" for name, value in point.settings])


def _sweep(args: argparse.Namespace, engine: Any, points: list[Any], options: tuple[str, ...], names: list[str],
           x: str, outputs: list[Path], program: str) -> int:
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn

    from orc_rpl.verify.plot import plot_outcomes
    from orc_rpl.verify.task import run_task

    specs = [spec_of(point, program, args.robot, args.world, options) for point in points]
    outcomes = [name.strip() for name in args.outcome.split(",") if name.strip()]
    status = Console(file=sys.stderr, soft_wrap=True)
    records: dict[int, dict[str, Any]] = {}
    interrupted = False
    start = time.perf_counter()
    progress = Progress(TextColumn("runs"), BarColumn(), MofNCompleteColumn(), TextColumn("ETA"),
                        TimeRemainingColumn(), console=status, disable=not status.is_terminal)
    with engine, progress:
        task = progress.add_task("runs", total=len(specs))
        try:
            for done in engine.results(run_task, specs, args.orc_main):
                record = record_of(done.index, points[done.index], done.result, done.attempts, done.failure)
                records[done.index] = record
                progress.advance(task)
                shown = ", ".join(f"{k}={record[k]}" for k in (*names, "seed", "variation") if k in record)
                got = ", ".join(f"{name}={record.get(name)}" for name in outcomes)
                progress.console.print(f"[{len(records)}/{len(specs)}] {shown}: {record['status']} {got}",
                                       markup=False, highlight=False)
        except KeyboardInterrupt:
            interrupted = True
    ordered = [records[i] for i in sorted(records)]
    csv_path, jsonl_path, png_path = outputs
    write_table(ordered, csv_path, jsonl_path)
    others = [n for n in names if n != x] + [k for k in ("variation",) if k != x and any(k in r for r in ordered)]
    plotted = plot_outcomes(ordered, x, outcomes, others, png_path, f"{Path(args.program).name}: {', '.join(outcomes)}")
    lost = sum(1 for r in ordered if r["status"] == "lost")
    status.print(f"{len(ordered)} of {len(specs)} runs ({time.perf_counter() - start:.1f} s wall); wrote {csv_path}, "
                 f"{jsonl_path}, {png_path} ({plotted} points of {', '.join(outcomes)})", markup=False, highlight=False)
    if interrupted:
        status.print("orc sweep: interrupted: the remaining runs were cancelled", markup=False, highlight=False)
        return 130
    return 1 if lost else 0
