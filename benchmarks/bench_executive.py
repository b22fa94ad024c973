"""Executive benchmark: interpreter overhead per statement, and a 1,000-motion program as a multiple of real time.

Run: python benchmarks/bench_executive.py [--iterations 200000] [--motions 1000] [--backend servo]
The last lines are `key=value` figures (targets: statements_per_s >= 200000, motion_program_x_realtime >= 50).
"""

from __future__ import annotations

import argparse
import math
import time

from orc_rpl.executive.cell_robot import CellRobot
from orc_rpl.executive.executive import Executive
from orc_rpl.executive.machine import Options
from orc_rpl.executive.recording_robot import RecordingRobot
from orc_rpl.syntax.parser import parse

#: Computation only: per iteration the WHILE condition, three assignments and an IF (5 simple statements).
COMPUTATION = """
VAR i = 0
VAR total = 0
VAR odd = 0
WHILE i < {n} DO
    i = i + 1
    total = total + i * 2
    IF i - (i / 2) * 2 <> 0 THEN
        odd = odd + 1
    ENDIF
ENDWHILE
PRINT total, odd
"""
COMPUTATION_STATEMENTS_PER_ITERATION = 5

#: Calls: a FUNC per iteration (call, RETURN, assignment, condition).
CALLS = """
FUNC twice(x)
    RETURN 2 * x
ENDFUNC
VAR i = 0
WHILE i < {n} DO
    i = i + twice(1) - 1
ENDWHILE
"""
CALLS_STATEMENTS_PER_ITERATION = 3

#: 1,000 motions round a rectangle in front of the robot, blended at the corners, with a FINE stop per lap.
MOTIONS = """
TOOL gripper = POSE(0, 0, 150mm, 0, 0, 0)
POS p1 = POSE(850mm, -250mm, 650mm, 0, 180deg, 0)
POS p2 = POSE(850mm, 250mm, 650mm, 0, 180deg, 0)
POS p3 = POSE(1050mm, 250mm, 550mm, 0, 180deg, 0)
POS p4 = POSE(1050mm, -250mm, 550mm, 0, 180deg, 0)
MOVE gripper TO p1
FOR lap FROM 1 TO {laps} DO
    LMOVE gripper TO p2 WITH SPEED = 1mps WITH ZONE = 20mm
    LMOVE gripper TO p3 WITH SPEED = 1mps WITH ZONE = 20mm
    LMOVE gripper TO p4 WITH SPEED = 1mps WITH ZONE = 20mm
    MOVE gripper TO p1
ENDFOR
"""


def rate(text: str, n: int, per_iteration: int, tracing: bool = False) -> float:
    """Simple statements per second of wall time."""
    # computation without motion is what the statement budget stops; the benchmark measures it unbounded
    executive = Executive(parse(text.format(n=n)), RecordingRobot(), output=lambda line: None,
                          options=Options(statement_budget=None))
    executive.tracing = tracing
    start = time.perf_counter()
    status = executive.run()
    wall_s = time.perf_counter() - start
    assert status == "finished", executive.report()
    return n * per_iteration / wall_s


class TimedRobot:
    """The robot with a stopwatch on what the motion core does (planning in submit, cycles in tick)."""

    def __init__(self, robot: CellRobot) -> None:
        self.robot, self.core_s = robot, 0.0
        self.dt_s, self.io = robot.dt_s, robot.io

    def tick(self) -> None:
        start = time.perf_counter()
        self.robot.tick()
        self.core_s += time.perf_counter() - start

    def submit(self, request: object) -> object:
        start = time.perf_counter()
        try:
            return self.robot.submit(request)  # type: ignore[arg-type]
        finally:
            self.core_s += time.perf_counter() - start

    def __getattr__(self, name: str) -> object:
        return getattr(self.robot, name)


def motion_program(motions: int, backend: str) -> tuple[float, float, float, int]:
    """(simulated s, wall s, motion core's wall s, motions) of the rectangle program on the virtual robot."""
    laps = max(1, math.ceil((motions - 1) / 4))
    robot = TimedRobot(CellRobot.virtual(backend=backend))
    executive = Executive(parse(MOTIONS.format(laps=laps)), robot, output=lambda line: None)  # type: ignore[arg-type]
    start = time.perf_counter()
    status = executive.run()
    wall_s = time.perf_counter() - start
    assert status == "finished", executive.report()
    return robot.time_s(), wall_s, robot.core_s, executive.motions


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--iterations", type=int, default=200_000)
    parser.add_argument("--motions", type=int, default=1000)
    parser.add_argument("--backend", choices=("servo", "kinematic"), default="servo",
                        help="servo: MuJoCo cell with the servo loop (the virtual robot of orc run); kinematic: no plant")
    args = parser.parse_args()

    computation = max(rate(COMPUTATION, args.iterations, COMPUTATION_STATEMENTS_PER_ITERATION) for _ in range(3))
    traced = rate(COMPUTATION, args.iterations // 4, COMPUTATION_STATEMENTS_PER_ITERATION, tracing=True)
    calls = rate(CALLS, args.iterations // 2, CALLS_STATEMENTS_PER_ITERATION)
    print(f"computation-only: {computation:,.0f} statements/s ({1e9 / computation:.0f} ns each); "
          f"traced for the pendant: {traced:,.0f}/s; with a FUNC call each: {calls:,.0f}/s")
    simulated_s, wall_s, core_s, motions = motion_program(args.motions, args.backend)
    share = 1.0 - core_s / wall_s
    print(f"{motions} motions on the {args.backend} cell: {simulated_s:.1f} s simulated in {wall_s:.1f} s wall, "
          f"of which the executive {100 * share:.1f} % (the rest is planning, servo and plant)")
    print(f"statements_per_s={computation:.0f}")
    print(f"statement_overhead_ns={1e9 / computation:.0f}")
    print(f"traced_statements_per_s={traced:.0f}")
    print(f"call_statements_per_s={calls:.0f}")
    print(f"motion_program_motions={motions}")
    print(f"motion_program_simulated_s={simulated_s:.3f}")
    print(f"motion_program_wall_s={wall_s:.2f}")
    print(f"motion_program_executive_share={share:.4f}")
    print(f"motion_program_x_realtime={simulated_s / wall_s:.1f}")


if __name__ == "__main__":
    main()
