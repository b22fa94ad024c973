"""Dummy sensors (thesis 5.2): the wall-clock standstill before a motion whose target a sensor gives, when it is
computed ahead from the sensor's dummy against when it is computed after the sensor has answered.

Run: python benchmarks/bench_sensor_ahead.py [--rounds 6]
The program moves above a seam, then onto it corrected by the laser's lateral offset (`MOVE torch TO
OFFS(OnSeam, LaserSensor.Distance, 0, 0) WITH KNOWN = "almost"`), then away, `rounds` times, run by the executive
on the realistic cell paced to the wall clock (what `orc run --realtime` does) with the simulated laser on a
ragged seam. With `INSTALL ... WITH DUMMY = 0mm` the approach to the seam is planned while the robot moves above
it, from the dummy's value, and corrected by the laser's answer; the baseline in the same run is the same
program without DUMMY (the dummy sees no seam, its worst case: the approach is planned when the laser has
answered, as before dummies were used). Printed (key=value, medians over the rounds):
  standstill_sensor_dummy_ms      wall clock from the end of the cycle that finished the move above the seam to
                                  the approach handed to the motion layer, ready for the next cycle
  standstill_sensor_at_start_ms   the same in the baseline
  standstill_sensor_saving_ms     their difference
  sensor_from_dummy, sensor_corrected, sensor_confirmed   the approaches computed from the dummy and what the
                                  laser's answer did to them; sensor_end_offset_max_mm: the laser's reading on
                                  the seam after the approach (how well the correction landed), largest;
                                  sensor_end_offset_max_at_start_mm: the same in the baseline
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

import numpy as np

from orc_rpl.executive.cell_robot import CellRobot
from orc_rpl.executive.executive import Executive
from orc_rpl.executive.sim_io import load_script
from orc_rpl.syntax.parser import parse

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_realtime_planning import Probe  # noqa: E402  (the same probe as planning ahead's figures)

ROOT = Path(__file__).resolve().parents[1]
PROGRAM = """\
TOOL torch = POSE(0, 0, 200mm, 0, 0, 0)
INSTALL LaserSensor AS LaserDistance WITH PORT = "sim"{dummy}
POS Above = POSE(1000mm, -200mm, 600mm, 0, 180deg, 0)
POS OnSeam = POSE(1000mm, -200mm, 500mm, 0, 180deg, 0)
POS Away = POSE(900mm, 100mm, 650mm, 0, 180deg, 0)
VAR worst = 0mm
LaserSensor.On
FOR i FROM 1 TO {rounds} DO
    MOVE torch TO Above
    MOVE torch TO OFFS(OnSeam, LaserSensor.Distance, 0, 0) WITH KNOWN = "almost"
    worst = MAX(worst, ABS(LaserSensor.Distance))
    MOVE torch TO Away
ENDFOR
PRINT worst / 1mm
"""


def run(rounds: int, dummy: bool) -> tuple[Probe, Executive, CellRobot]:
    robot = CellRobot.virtual(realtime=True)
    probe = Probe(robot)
    text = PROGRAM.format(rounds=rounds, dummy=" WITH DUMMY = 0mm" if dummy else "")
    executive = Executive(parse(text, "bench.rpl"), robot, path="bench.rpl", source=text, output=lambda line: None)
    load_script(ROOT / "programs/online/demo_sensor_ahead.sim.yaml", robot.io,
                lambda: robot.tcp_pose(executive.machine.last_tool))
    executive.run()
    assert executive.status == "finished", executive.report()
    return probe, executive, robot


def sensor_standstills_s(probe: Probe) -> list[float]:
    """The standstills before the approaches: the second motion of each round of three."""
    return probe.standstills_s()[0::3]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=6)
    args = parser.parse_args()
    print(f"load_average_1min={os.getloadavg()[0]:.2f}")
    baseline, plain, _ = run(args.rounds, dummy=False)
    ahead, executive, robot = run(args.rounds, dummy=True)
    ms = 1000.0
    with_dummy, at_start = np.median(sensor_standstills_s(ahead)), np.median(sensor_standstills_s(baseline))
    print(f"rounds={args.rounds}")
    print(f"cycle_ms={robot.dt_s * ms:.1f}")
    print(f"standstill_sensor_dummy_ms={with_dummy * ms:.2f}")
    print(f"standstill_sensor_dummy_max_ms={max(sensor_standstills_s(ahead)) * ms:.2f}")
    print(f"standstill_sensor_at_start_ms={at_start * ms:.2f}")
    print(f"standstill_sensor_at_start_max_ms={max(sensor_standstills_s(baseline)) * ms:.2f}")
    print(f"standstill_sensor_saving_ms={(at_start - with_dummy) * ms:.2f}")
    counts = robot.planning
    print(f"sensor_from_dummy={counts.from_dummy}")
    print(f"sensor_corrected={counts.corrected}")
    print(f"sensor_confirmed={counts.confirmed}")
    print(f"sensor_end_offset_max_mm={float(executive.prints[-1]):.3f}")
    print(f"sensor_end_offset_max_at_start_mm={float(plain.prints[-1]):.3f}")


if __name__ == "__main__":
    main()
