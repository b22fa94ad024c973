"""Pendant latency: a jog key press to the motion command reaching the motion layer, and a typed statement to its motion.

Drives the real terminal application (prompt-toolkit, pipe input, dummy output) on the virtual robot and times,
from the moment the key's bytes are written, until `MotionLayer.move` is entered (the command reached the motion
layer) and until it returns (the motion is planned and queued: it starts at the next motion cycle).
Target: jog p99 under 10 ms.
"""

from __future__ import annotations

import argparse
import asyncio
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
from prompt_toolkit.input import create_pipe_input
from prompt_toolkit.output import DummyOutput

from orc_rpl.pendant.app import PendantApp
from orc_rpl.pendant.robot import PendantRobot
from orc_rpl.pendant.session import PendantSession

PROGRAM = """\
FRAME base_plate = POSE(900mm, 0, 500mm, 0, 0, 0)
POS pos0 = POSE(800mm, -300mm, 800mm, 0, 180deg, 0)
POS pos3 = POSE(800mm, 300mm, 800mm, 0, 180deg, 0)
POS pos1 = POSE(100mm, -100mm, 50mm, 0, 180deg, 0) IN base_plate
MOVE ARM TO pos0
FRAME base_plate
    MOVE ARM TO pos1
ENDFRAME
"""
RIGHT, LEFT = "\x1b[C", "\x1b[D"


class Probe:
    """Wraps MotionLayer.move: when each call came in and how long it took."""

    def __init__(self, layer: Any) -> None:
        self.entered: list[float] = []
        self.returned: list[float] = []
        original = layer.move

        def move(*args: Any, **kwargs: Any) -> Any:
            self.entered.append(time.perf_counter())
            try:
                return original(*args, **kwargs)
            finally:
                self.returned.append(time.perf_counter())

        layer.move = move


async def _until(condition: Any, timeout_s: float = 30.0) -> None:
    end = time.perf_counter() + timeout_s
    while not condition():
        if time.perf_counter() > end:
            raise TimeoutError("the pendant did not react")
        await asyncio.sleep(0)


async def measure(session: PendantSession, presses: int, statements: int) -> dict[str, list[float]]:
    probe = Probe(session.robot.layer)
    jog_in, jog_out, typed_in, typed_out = [], [], [], []
    with create_pipe_input() as pipe:
        app = PendantApp(session, input=pipe, output=DummyOutput(), realtime=False)
        task = asyncio.ensure_future(app.run_async())
        await asyncio.sleep(0.2)
        session.jogger.cycle_increment()  # 0.1 mm / 0.1 deg: short motions, the robot stays where it is
        for i in range(presses):
            count = len(probe.entered)
            start = time.perf_counter()
            pipe.send_text(RIGHT if i % 2 == 0 else LEFT)
            await _until(lambda: len(probe.returned) > count)
            jog_in.append(probe.entered[count] - start)
            jog_out.append(probe.returned[count] - start)
            await _until(lambda: session.robot.pending() == 0)
        for i in range(statements):
            pipe.send_text("MOVE ARM TO pos0" if i % 2 == 0 else "MOVE ARM TO pos3")
            await asyncio.sleep(0.05)  # the characters are typed; now Enter
            count = len(probe.entered)
            start = time.perf_counter()
            pipe.send_text("\r")
            await _until(lambda: len(probe.returned) > count)
            typed_in.append(probe.entered[count] - start)
            typed_out.append(probe.returned[count] - start)
            await _until(lambda: not session.execution.busy and session.robot.pending() == 0)
        pipe.send_text(":quit!\r")
        await task
    return {"jog_in": jog_in, "jog_out": jog_out, "typed_in": typed_in, "typed_out": typed_out}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--presses", type=int, default=300)
    parser.add_argument("--statements", type=int, default=40)
    parser.add_argument("--backend", choices=("servo", "kinematic"), default="servo")
    args = parser.parse_args()
    folder = Path(tempfile.mkdtemp())
    (folder / "bench.rpl").write_text(PROGRAM, encoding="utf-8")
    session = PendantSession(folder / "bench.rpl", robot=PendantRobot.virtual(backend=args.backend),
                             synchronous=False, journal=False)
    results = asyncio.run(measure(session, args.presses, args.statements))
    ms = {key: np.array(values) * 1000.0 for key, values in results.items()}
    for key, label in (("jog_in", "jog key -> motion layer"), ("jog_out", "jog key -> motion planned"),
                       ("typed_in", "typed statement -> motion layer"), ("typed_out", "typed statement -> motion planned")):
        v = ms[key]
        print(f"{label:36} p50 {np.percentile(v, 50):6.2f} ms  p99 {np.percentile(v, 99):6.2f} ms  "
              f"max {v.max():6.2f} ms  ({len(v)} samples, {args.backend} robot)")
    print(f"jog_p50_ms={np.percentile(ms['jog_in'], 50):.3f}")
    print(f"jog_p99_ms={np.percentile(ms['jog_in'], 99):.3f}")
    print("jog_p99_target_ms=10")
    print(f"jog_planned_p99_ms={np.percentile(ms['jog_out'], 99):.3f}")
    print(f"typed_statement_p50_ms={np.percentile(ms['typed_in'], 50):.3f}")
    print(f"typed_statement_p99_ms={np.percentile(ms['typed_in'], 99):.3f}")
    print(f"typed_statement_planned_p99_ms={np.percentile(ms['typed_out'], 99):.3f}")


if __name__ == "__main__":
    main()
