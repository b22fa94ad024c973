"""Fuzz benchmark: seeded hostile inputs in-process; every one must end in a located error or a result, quickly.

Run: python benchmarks/bench_fuzz.py [--programs 20000] [--worlds 20000] [--pendant-lines 5000] [--seed 1]
Each program is parsed and checked (`orc check`'s check_file, its world model included for off-line ones),
each world loaded (`load_world_file`), each pendant line run headless on a session over the kinematic
robot. The last lines are `key=value` figures (targets: internal_errors=0, hangs_over_5s=0,
unlocated_errors=0). An input that takes longer than 5 s counts as a hang; one that takes 60 s is
abandoned (SIGALRM) so that the benchmark always ends.
"""

from __future__ import annotations

import argparse
import os
import random
import shutil
import signal
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tests.fuzz_inputs: the generators the tests use

from orc_rpl.application.registry import default_registry  # noqa: E402
from orc_rpl.commands.check import check_file  # noqa: E402
from orc_rpl.errors import Diagnostic, OrcError, SourceError  # noqa: E402
from orc_rpl.transform.checks import load_world_file  # noqa: E402
from tests import fuzz_inputs  # noqa: E402

HANG_S = 5.0
ABANDON_S = 60


class Abandoned(Exception):
    """An input that ran past ABANDON_S."""


class Tally:
    """Counts of one input kind."""

    def __init__(self, kind: str) -> None:
        self.kind = kind
        self.inputs = self.internal = self.hangs = self.unlocated = self.rejected = 0
        self.slowest_s = 0.0
        self.examples: list[str] = []

    def note(self, what: str, detail: str) -> None:
        if len(self.examples) < 5:
            self.examples.append(f"{self.kind} {what}: {detail[:200]!r}")


def unlocated(diagnostics: list[Diagnostic]) -> int:
    """Diagnostics about a file's content that have no line and column."""
    return sum(1 for d in diagnostics if d.location.line < 1 or d.location.column < 1)


def internal(diagnostics: list[Diagnostic]) -> int:
    return sum(1 for d in diagnostics if "internal error" in d.message)


def timed(tally: Tally, label: str, job: Callable[[], None]) -> None:
    """Run one input, classify what escapes, and time it (abandoned after ABANDON_S)."""
    tally.inputs += 1
    signal.alarm(ABANDON_S)
    start = time.perf_counter()
    try:
        job()
    except Abandoned:
        tally.note("abandoned", label)
    except OrcError:
        tally.rejected += 1
    except Exception as error:  # anything else reached the user as a traceback
        tally.internal += 1
        tally.note("internal", f"{label}: {type(error).__name__}: {error}")
    finally:
        signal.alarm(0)
    took_s = time.perf_counter() - start
    tally.slowest_s = max(tally.slowest_s, took_s)
    if took_s > HANG_S:
        tally.hangs += 1
        tally.note("hang", f"{label} ({took_s:.1f} s)")


def fuzz_programs(count: int, seed: int, scratch: Path) -> Tally:
    registry = default_registry()
    tally = Tally("program")
    rng = random.Random(seed)
    for index in range(count):
        suffix, text = fuzz_inputs.program(rng)
        path = scratch / "programs" / ("offline" if suffix == ".orl" else "online") / f"gen{suffix}"
        path.write_text(text, encoding="utf-8")

        def job() -> None:
            _, diagnostics = check_file(str(path), registry)
            tally.unlocated += unlocated(diagnostics)
            found = internal(diagnostics)
            tally.internal += found
            if found or unlocated(diagnostics):
                tally.note("diagnostic", text[:120])
        timed(tally, f"program {index}", job)
    return tally


def fuzz_worlds(count: int, seed: int, scratch: Path) -> Tally:
    tally = Tally("world")
    rng = random.Random(seed + 1)
    path = scratch / "worlds" / "gen.yaml"
    for index in range(count):
        path.write_text(fuzz_inputs.world(rng), encoding="utf-8")

        def job() -> None:
            try:
                load_world_file(path)
            except SourceError as error:
                tally.unlocated += unlocated(error.diagnostics)
                tally.internal += internal(error.diagnostics)
                raise
        timed(tally, f"world {index}", job)
    return tally


def fuzz_pendant(count: int, seed: int, scratch: Path) -> Tally:
    from orc_rpl.pendant.commands import run_line
    from orc_rpl.pendant.robot import PendantRobot
    from orc_rpl.pendant.session import PendantSession
    from tests.pendant.support import FRAME_PROGRAM

    tally = Tally("pendant line")
    rng = random.Random(seed + 2)
    session = None
    for index in range(count):
        if index % 100 == 0:  # a fresh session now and then, as a person restarts the pendant
            (scratch / "cell.rpl").write_text(FRAME_PROGRAM, encoding="utf-8")
            session = PendantSession(scratch / "cell.rpl", robot=PendantRobot.virtual(backend="kinematic"))
        line = fuzz_inputs.pendant_line(rng)

        def job() -> None:
            outcome = run_line(session, line)  # type: ignore[arg-type]
            if "internal error" in outcome.text or "Traceback" in outcome.text:
                tally.internal += 1
                tally.note("internal", f"{line!r}: {outcome.text}")
        timed(tally, f"pendant line {index} {line[:40]!r}", job)
    return tally


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--programs", type=int, default=20000)
    parser.add_argument("--worlds", type=int, default=20000)
    parser.add_argument("--pendant-lines", type=int, default=5000)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()

    def abandon(signum: int, frame: object) -> None:
        raise Abandoned()
    signal.signal(signal.SIGALRM, abandon)

    scratch = Path(tempfile.mkdtemp(prefix="orc-bench-fuzz-"))
    root = Path(__file__).resolve().parents[1]
    shutil.copytree(root / "worlds", scratch / "worlds")
    for folder in ("online", "offline"):
        (scratch / "programs" / folder).mkdir(parents=True)
    cwd = os.getcwd()
    os.chdir(scratch)  # pendant lines such as `:save copy.rpl` write here
    wall_start = time.perf_counter()
    tallies: list[Tally] = []
    try:
        for run, count in ((fuzz_programs, args.programs), (fuzz_worlds, args.worlds), (fuzz_pendant, args.pendant_lines)):
            tallies.append(run(count, args.seed, scratch))
            done = tallies[-1]
            print(f"{done.kind}s done: {done.inputs} inputs, {time.perf_counter() - wall_start:.0f} s so far", flush=True)
    finally:
        os.chdir(cwd)
        shutil.rmtree(scratch, ignore_errors=True)
    wall_s = time.perf_counter() - wall_start
    for tally in tallies:
        print(f"{tally.kind}s: {tally.inputs} inputs, {tally.rejected} rejected with an error, {tally.internal} internal "
              f"errors, {tally.hangs} over {HANG_S:g} s, {tally.unlocated} unlocated, slowest {tally.slowest_s:.2f} s")
        for example in tally.examples:
            print("  " + example)
    names = {"program": "programs", "world": "worlds", "pendant line": "pendant_lines"}
    for tally in tallies:
        print(f"{names[tally.kind]}_inputs={tally.inputs}")
        print(f"{names[tally.kind]}_slowest_s={tally.slowest_s:.3f}")
    print(f"inputs={sum(t.inputs for t in tallies)}")
    print(f"internal_errors={sum(t.internal for t in tallies)}")
    print(f"hangs_over_5s={sum(t.hangs for t in tallies)}")
    print(f"unlocated_errors={sum(t.unlocated for t in tallies)}")
    print(f"wall_s={wall_s:.1f}")


if __name__ == "__main__":
    main()
