"""Off-line <-> on-line transformation of a 5,000-statement program with a 2,000-object world, both ways (target under 2 s each).

The world is generated: 100 fixtures on a table, 40 of them tagged on-line frames, each with parts and named
frames below it, tools on holders at the flange. The program moves through the world's positions inside loops,
branches and procedures. Reading and printing the files is timed apart from the transformation itself: reading
the world and parsing the program as one `orc check --world` does, in fresh processes (medians of --runs).
Run: python benchmarks/bench_transform.py
"""

from __future__ import annotations

import argparse
import json
import os
import random
import statistics
import subprocess
import sys
import time

from orc_rpl.syntax.offline_parser import parse_offline
from orc_rpl.syntax.offline_printer import print_offline
from orc_rpl.syntax.parser import parse
from orc_rpl.syntax.printer import print_program
from orc_rpl.transform.pipeline import to_offline, to_online
from orc_rpl.world import loads_world


def make_world(objects: int, rng: random.Random) -> tuple[str, list[str]]:
    """World text with `objects` objects and the dotted positions a program may use."""
    lines = ["# generated for bench_transform.py", "robot:", "  model: irb2400", "  pose: [0, 0, 0, 0, 0, 0]", "", "world:",
             "  table:", "    pose: [1000mm, 0, 600mm, 0, 0, 0]", "    model:", "      geometry: box",
             "      size: [600mm, 1000mm, 600mm]"]
    positions: list[str] = []
    count, fixture = 1, 0
    while count < objects - 4:
        fixture += 1
        name = f"fixture{fixture}"
        lines += [f"  {name}:", "    parent: table", f"    pose: [{rng.randint(-250, 250)}mm, {rng.randint(-400, 400)}mm, 0, 0, 0, 0]"]
        if fixture % 5 < 2:
            lines.append("    online_frame: true")
        lines += ["    model:", "      geometry: box", "      size: [100mm, 100mm, 20mm]"]
        count += 1
        parent = name
        for part in range(min(18, objects - 4 - count)):
            child = f"{name}_part{part}"
            lines += [f"  {child}:", f"    parent: {parent}", f"    pose: [{rng.randint(-30, 30)}mm, {rng.randint(-30, 30)}mm, 5mm, 0, 0, 0]"]
            if part % 6 == 0:
                lines.append("    online_frame: true")
            lines += ["    frames:", "      p: [0, 0, 100mm, 0, 180deg, 0]", f"      above: [0, 0, {rng.randint(150, 250)}mm, 0, 180deg, 0]"]
            positions += [f"{child}.p", f"{child}.above"]
            count += 1
            parent = child if part % 3 == 2 else parent
    lines += ["  holder:", "    parent: flange", "    pose: [0, 0, 60mm, 0, 0, 0]",
              "  grinder:", "    parent: holder", "    pose: [20mm, 0, 120mm, 0, 0, 0]", "    tool: true",
              "  gripper:", "    parent: flange", "    pose: [0, 0, 180mm, 0, 0, 0]", "    tool: true"]
    return "\n".join(lines) + "\n", positions


def make_program(statements: int, positions: list[str], rng: random.Random) -> str:
    """Off-line text of about `statements` statements."""
    lines = ["# generated for bench_transform.py", "const Vmax = 1.5mps", "n = 0"]
    made = 0
    while made < statements:
        kind = rng.random()
        if kind < 0.6:
            lines.append(f"move {rng.choice(['gripper', 'grinder'])} to {rng.choice(positions)} speed=0.5 * Vmax")
            made += 1
        elif kind < 0.8:
            lines.append("for i in 1..3:")
            for _ in range(3):
                lines.append(f"    moveto {rng.choice(positions)}")
            made += 4
        elif kind < 0.9:
            lines += ["if n > 3:", f"    moveto {rng.choice(positions)}", "else:", "    n = n + 1"]
            made += 3
        else:
            lines += ["# a comment", "wait 10ms"]
            made += 1
    return "\n".join(lines) + "\n"


def _read_once(objects: int, statements: int) -> dict[str, float]:
    """Read the world and parse the program once, as one `orc check --world` does in a fresh process."""
    rng = random.Random(7)
    world_text, positions = make_world(objects, rng)
    program_text = make_program(statements, positions, rng)
    t0 = time.perf_counter()
    loads_world(world_text, "bench.yaml")
    t1 = time.perf_counter()
    parse_offline(program_text, "bench.orl")
    t2 = time.perf_counter()
    return {"read_world_s": t1 - t0, "parse_offline_program_s": t2 - t1, "read_world_and_program_s": t2 - t0}


def _fresh_reads(objects: int, statements: int, runs: int) -> dict[str, float]:
    """Medians of `runs` reads, each in a fresh Python process (nothing warm but the parser cache on disk)."""
    samples: dict[str, list[float]] = {}
    for _ in range(runs):
        out = subprocess.run([sys.executable, __file__, "--read-once", "--objects", str(objects), "--statements", str(statements)],
                             check=True, capture_output=True, text=True).stdout
        for key, value in json.loads(out.splitlines()[-1]).items():
            samples.setdefault(key, []).append(value)
    return {key: statistics.median(values) for key, values in samples.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--statements", type=int, default=5000)
    ap.add_argument("--objects", type=int, default=2000)
    ap.add_argument("--runs", type=int, default=5, help="fresh processes the reading times are the medians of")
    ap.add_argument("--read-once", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.read_once:
        print(json.dumps(_read_once(args.objects, args.statements)))
        return
    rng = random.Random(7)
    world_text, positions = make_world(args.objects, rng)
    program_text = make_program(args.statements, positions, rng)

    world = loads_world(world_text, "bench.yaml")   # also writes the parsers' cache, as any first orc command does
    program = parse_offline(program_text, "bench.orl")
    reads = _fresh_reads(args.objects, args.statements, args.runs)
    t1 = time.perf_counter()
    job = to_online(program, world, "bench.orl", program_text)
    t2 = time.perf_counter()
    online_text = print_program(job.program)
    online = parse(online_text, "bench.rpl")
    t3 = time.perf_counter()
    back = to_offline(online, world, "bench.rpl")
    t4 = time.perf_counter()
    exact = print_offline(back.program) == print_offline(program) and back.world.dump() == world_text
    statements = sum(1 for line in program_text.splitlines() if line.strip() and not line.lstrip().startswith("#"))

    print(f"world_objects={len(world.objects)}")
    print(f"program_statements={statements}")
    print(f"online_lines={online_text.count(chr(10))}")
    print(f"load_average_1min={os.getloadavg()[0]:.2f}")
    # Baseline in the same run: ruamel composing the same text (how every world was read before libyaml).
    from ruamel.yaml import YAML

    r0 = time.perf_counter()
    YAML(typ="rt").compose(world_text)
    ruamel_s = time.perf_counter() - r0
    print(f"reading_runs={args.runs}")
    print(f"read_world_s={reads['read_world_s']:.3f}")
    print(f"ruamel_compose_world_s={ruamel_s:.3f}")
    print(f"read_world_over_ruamel_compose_ratio={reads['read_world_s'] / ruamel_s:.3f}")
    print(f"parse_offline_program_s={reads['parse_offline_program_s']:.3f}")
    print(f"read_world_and_program_s={reads['read_world_and_program_s']:.3f}")
    print(f"print_and_parse_online_s={t3 - t2:.3f}")
    print(f"round_trip_exact={exact}")
    print(f"to_online_s={t2 - t1:.3f}")
    print(f"to_offline_s={t4 - t3:.3f}")


if __name__ == "__main__":
    main()
