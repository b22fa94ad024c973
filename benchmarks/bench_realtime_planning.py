"""Planning ahead under --realtime: the wall-clock standstill between consecutive FINE motions, and the motion cycle's
jitter while the next motion is planned on the worker thread.

Run: python benchmarks/bench_realtime_planning.py [--rounds 2]
The program is a cycle of FINE motions (MOVE and LMOVE) run by the executive on the simulated cell paced to the wall
clock (what `orc run --realtime` does). Baseline in the same run: the same program with every motion planned when it
is submitted (no worker), as before planning ahead. Printed (key=value, medians over the motion pairs):
  standstill_ahead_ms       wall clock from the end of the cycle that finished one FINE motion to the next motion
                            handed to the motion layer, ready for the next cycle (target: under one motion cycle)
  standstill_at_start_ms    the same, planned when submitted (the baseline)
  cycle_ms                  the motion cycle
  late_while_planning_ms    the motion cycle's lateness (wall clock behind its schedule) in cycles during which the
                            worker is planning: p99 and max (target: p99 under one cycle)
  late_at_start_max_ms      the baseline's worst lateness (the cycle that waited for the plan)
  idle_cycles_*_max         cycles commanding no motion between a FINE motion's end and the next one's first cycle
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from orc_rpl.executive.cell_robot import CellRobot
from orc_rpl.executive.executive import Executive
from orc_rpl.motion.layer import MotionLayer
from orc_rpl.syntax.parser import parse

PROGRAM = """\
POS p1 = POSE(800mm, -300mm, 900mm, 0, 180deg, 0)
POS p2 = POSE(1100mm, -200mm, 800mm, 0, 180deg, 0)
POS p3 = POSE(900mm, 200mm, 850mm, 0, 180deg, 0)
FOR i FROM 1 TO {rounds} DO
    MOVE ARM TO p1
    MOVE ARM TO p2
    LMOVE ARM TO p3
    MOVE ARM TO p2
ENDFOR
"""


class Probe:
    """On one robot: when each move ended (the end of the cycle that finished it, wall clock and cycle number), when
    the next was handed over (wall clock) and started (cycle number), and each cycle's lateness."""

    def __init__(self, robot: CellRobot) -> None:
        layer = self.layer = robot.layer
        self.ends: list[tuple[float, int]] = []        # (wall clock after the cycle that finished a move, cycle)
        self.submitted: list[float] = []                # wall clock when a move was handed over (planned or recalled)
        self.starts: list[int] = []                     # cycle in which a move's first reference was commanded
        self.late_planning_s: list[float] = []
        self.late_other_s: list[float] = []
        start, pace, submit, tick = layer._start, layer._pace, robot.submit, robot.tick

        def on_start(h):  # type: ignore[no-untyped-def]
            self.starts.append(layer.cycles)
            return start(h)

        def on_tick() -> None:
            busy = robot.pending() > 0
            tick()
            if busy and robot.pending() == 0:  # this cycle ended the last move: the robot stands from here
                self.ends.append((time.perf_counter(), layer.cycles))

        def on_pace() -> None:
            if layer._wall_start is not None:
                late = time.perf_counter() - (layer._wall_start + layer.now_s())
                planning = layer.ahead is not None and any(not j.future.done() for j in layer.ahead._jobs.values())
                (self.late_planning_s if planning else self.late_other_s).append(max(0.0, late))
            pace()

        def on_submit(request):  # type: ignore[no-untyped-def]
            ticket = submit(request)
            self.submitted.append(time.perf_counter())
            return ticket

        layer._start, layer._pace = on_start, on_pace  # type: ignore[method-assign]
        robot.submit, robot.tick = on_submit, on_tick  # type: ignore[method-assign]

    def standstills_s(self) -> list[float]:
        """From the end of the cycle that finished a move to the next move handed over: what the cycle waits for."""
        return [self.submitted[i + 1] - self.ends[i][0] for i in range(min(len(self.ends), len(self.submitted) - 1))]

    def idle_cycles(self) -> list[int]:
        """Cycles commanding no motion between a move's end and the next move's first cycle."""
        return [self.starts[i + 1] - self.ends[i][1] for i in range(min(len(self.ends), len(self.starts) - 1))]


def run(rounds: int, ahead: bool) -> Probe:
    robot = CellRobot.virtual(realtime=True)
    if not ahead:
        robot.layer.ahead = None
    probe = Probe(robot)
    text = PROGRAM.format(rounds=rounds)
    executive = Executive(parse(text, "bench.rpl"), robot, path="bench.rpl", source=text, output=lambda line: None)
    executive.run()
    assert executive.status == "finished", executive.report()
    return probe


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=2, help="times the four FINE motions are run")
    args = parser.parse_args()
    print(f"load_average_1min={os.getloadavg()[0]:.2f}")
    baseline = run(args.rounds, ahead=False)
    planned = run(args.rounds, ahead=True)
    cycle_s = CellRobot.virtual().layer.dt_s
    ms = 1000.0
    print(f"motion_pairs={len(planned.standstills_s())}")
    print(f"cycle_ms={cycle_s * ms:.1f}")
    print(f"standstill_ahead_ms={np.median(planned.standstills_s()) * ms:.2f}")
    print(f"standstill_ahead_max_ms={max(planned.standstills_s()) * ms:.2f}")
    print(f"standstill_at_start_ms={np.median(baseline.standstills_s()) * ms:.2f}")
    print(f"standstill_at_start_max_ms={max(baseline.standstills_s()) * ms:.2f}")
    late = np.array(planned.late_planning_s or [0.0])
    print(f"cycles_while_planning={len(planned.late_planning_s)}")
    print(f"late_while_planning_p99_ms={np.percentile(late, 99) * ms:.2f}")
    print(f"late_while_planning_max_ms={late.max() * ms:.2f}")
    other = np.array(planned.late_other_s or [0.0])
    print(f"late_not_planning_p99_ms={np.percentile(other, 99) * ms:.2f}")
    print(f"late_at_start_max_ms={max(baseline.late_other_s or [0.0]) * ms:.2f}")
    print(f"idle_cycles_ahead_max={max(planned.idle_cycles())}")
    print(f"idle_cycles_at_start_max={max(baseline.idle_cycles())}")
    print(f"standstill_under_one_cycle={np.median(planned.standstills_s()) < cycle_s}")


if __name__ == "__main__":
    main()
