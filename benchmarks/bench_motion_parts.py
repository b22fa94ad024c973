"""The motion layer's cost per part, CPU time per simulated second, on bench_motion's program (elastic gears, state feedback).

Run: python benchmarks/bench_motion_parts.py [--robot irb2400] [--seconds 60] [--rounds 3]
bench_motion.py's `motion_layer_ms_per_sim_s_elastic_state_feedback` says how much wall time per simulated
second is spent above the servo; this says where, in the CPU time of the thread (time.thread_time: less
sensitive than the wall to the other programs on the machine), part by part: the planning on the motion
thread (the plan's geometry and IK along Cartesian paths, timing from rest, zone blends re-timed as they
start) and the motion cycle's parts (the path velocity controller, its time-scaled cycles, the estimates,
the recorder). Each part is measured around its function (inclusive: a blend's figure holds its toppra
run), which adds about a microsecond a call; `motion_layer_cpu_ms_per_sim_s` is the whole program loop's
CPU time less the servo's and plant's (`layer.backend.advance`).

The baseline in the same run, `_reference`, plans with the Python references of this code's compiled and
lean paths: the IK tracking in Python (Kinematics.compiled_tracking False) and toppra's own TOPP-RA passes
(timing.LEAN_PASSES False: neither the lean nor the compiled passes of toppra_passes.py); runs alternate, the
median of `--rounds` runs of each is printed. The recordings are those of bench_motion's speed runs (the same
program, the same plant).
"""

from __future__ import annotations

import argparse
import collections
import functools
import statistics
import time
from collections.abc import Callable
from typing import Any

import bench_motion as bm

from orc_rpl.arm import pvc
from orc_rpl.motion import make_virtual_motion_layer, pipeline, planner, timing
from orc_rpl.signals import logger

#: (printed name, owner, attribute) of the functions measured
PARTS = (
    ("planning_plan_geometry_ik", planner.Planner, "plan"),
    ("planning_timing_from_rest", planner.Planner, "time"),
    ("planning_zone_blends", pipeline.MotionPipeline, "_try_blend"),
    ("cycle_pvc", pvc.PathVelocityController, "cycle"),
    ("cycle_pvc_time_scaled", pvc.PathVelocityController, "_scaled"),
    ("cycle_estimates", pipeline, "update_estimates"),
    ("cycle_recorder", logger.Logger, "update"),
)
ELASTIC_STATE_FEEDBACK = {"elastic": True, "gear_feedforward": True, "state_feedback": True}
clock = time.thread_time


def _timed(totals: collections.Counter[str], name: str, function: Callable[..., Any]) -> Callable[..., Any]:
    @functools.wraps(function)
    def timed(*args: Any, **kwargs: Any) -> Any:
        start = clock()
        try:
            return function(*args, **kwargs)
        finally:
            totals[name] += clock() - start

    return timed


def one_run(robot: str, seconds: float, reference: bool) -> dict[str, float]:
    """CPU ms per simulated second of each part, and of the whole motion layer, in one run of the program."""
    totals: collections.Counter[str] = collections.Counter()
    originals = [(owner, attribute, getattr(owner, attribute)) for _, owner, attribute in PARTS]
    lean = timing.LEAN_PASSES
    timing.LEAN_PASSES = not reference
    try:
        for (name, owner, attribute), (_, _, function) in zip(PARTS, originals):
            setattr(owner, attribute, _timed(totals, name, function))
        layer = make_virtual_motion_layer(robot, backend="servo", record=True, plant="realistic", **ELASTIC_STATE_FEEDBACK)
        layer.kin.compiled_tracking = not reference
        layer.backend.advance = _timed(totals, "servo_and_plant", layer.backend.advance)  # type: ignore[method-assign]
        totals.clear()
        start, i = clock(), 0
        while layer.now_s() < seconds:
            bm.program_step(layer, i)
            i += 1
        loop_s, simulated_s = clock() - start, layer.now_s()
    finally:
        timing.LEAN_PASSES = lean
        for owner, attribute, function in originals:
            setattr(owner, attribute, function)
    out = {name: 1000.0 * totals[name] / simulated_s for name, _, _ in PARTS}
    out["motion_layer"] = 1000.0 * (loop_s - totals["servo_and_plant"]) / simulated_s
    out["servo_and_plant"] = 1000.0 * totals["servo_and_plant"] / simulated_s
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robot", default="irb2400")
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    one_run(args.robot, 6.0, False)  # warm-up: imports (toppra pulls in matplotlib), the kernels' cache
    one_run(args.robot, 6.0, True)
    runs: dict[bool, list[dict[str, float]]] = {False: [], True: []}
    for _ in range(args.rounds):
        for reference in (True, False):
            runs[reference].append(one_run(args.robot, args.seconds, reference))
    print(f"robot={args.robot}")
    print(f"plant=realistic_elastic_state_feedback seconds={args.seconds:g} rounds={args.rounds}")
    for name in [*(p[0] for p in PARTS), "servo_and_plant", "motion_layer"]:
        for reference, suffix in ((True, "_reference"), (False, "")):
            value = statistics.median(run[name] for run in runs[reference])
            print(f"{name}_cpu_ms_per_sim_s{suffix}={value:.3f}")
    ratio = statistics.median(run["motion_layer"] for run in runs[False]) / statistics.median(
        run["motion_layer"] for run in runs[True])
    print(f"motion_layer_cpu_vs_reference={ratio:.3f}")


if __name__ == "__main__":
    main()
