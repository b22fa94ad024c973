"""External axes benchmark: coordinated motion on the turning positioner, measured in the simulated cell.

Run: python benchmarks/bench_external_axes.py [--plant realistic|elastic-gears|ideal] [--seed 1] [--whole-periods]

The cell is worlds/positioner_cell.yaml: the robot on its track, the plate on the positioner's turn table.
The torch moves along the plate's seam (200 mm) while the table turns a quarter and the track carries the
robot 200 mm, one LMOVE in one path coordinate (the arm, the track and the turn each a stage of it). Every
motion cycle the TCP is measured relative to the plate, both from the plant (MuJoCo's flange and table
bodies), and its distance from the programmed straight seam is taken: `coordinated_tcp_dev_mm` (the largest;
target at most 0.5). Baseline in the same run, the same motion with the axes' drives given their reference
alone, without the lead that makes up for their time lag (what a stage that did not know its lag would do):
`no_lead_tcp_dev_mm`. Also printed: the motion's duration against the shortest the turn's speed and
acceleration limits allow (`duration_over_turn_limit`), and the axes' final errors. --whole-periods: on elastic
gears, every move from rest averaged over the gears' whole periods (make_virtual_motion_layer(...,
scaled_averaging=False)), not over as much of them as its steps twist them (the default; docs/motion.md,
"Averaging on elastic gears").
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from orc_rpl.motion import CartesianMotion, Params, make_virtual_motion_layer  # noqa: E402
from orc_rpl.motion.external import coordinated_motion, external_axes_of, shortest_time_s, world_frame_in_base  # noqa: E402
from orc_rpl.plant.world_scene import cell_from_world  # noqa: E402
from orc_rpl.robot.plants import SIMULATED_PLANTS  # noqa: E402
from orc_rpl.world import load_world  # noqa: E402
from orc_rpl.world.pose import Pose  # noqa: E402

CELL = Path(__file__).resolve().parents[1] / "worlds" / "positioner_cell.yaml"
TARGETS = {"turn": math.pi / 2, "track": 0.2}


def run(plant: str, seed: int, lead: bool, scaled_averaging: bool | None = None) -> dict[str, float]:
    """One coordinated seam: the largest TCP deviation from the seam relative to the plate, and what it took."""
    world = load_world(CELL)
    layer = make_virtual_motion_layer(cell=cell_from_world(world), plant=plant, seed=seed,
                                      scaled_averaging=scaled_averaging)
    layer.external = external_axes_of(world)
    backend = layer.backend
    if not lead:
        drive = backend.drive_axes
        backend.drive_axes = lambda refs, period: drive({k: (e, 0.0, 0.0) for k, (e, _, _) in refs.items()}, period)
    cell = backend.loop.cell
    tool = world.tool_pose("torch").matrix()
    h = layer.move(CartesianMotion(Pose.from_matrix(world.relative_pose("plate.seam_start", "robot").matrix()), kind="joint", tool=tool))
    layer.wait(h)
    layer.run_for(0.3)
    a = world.relative_pose("plate.seam_start", "plate").matrix()
    b = world.relative_pose("plate.seam_end", "plate").matrix()
    motion = coordinated_motion(world_frame_in_base(world, "plate"), a, b, {"turn": 0.0, "track": 0.0}, TARGETS, tool)
    h = layer.external.request(layer, motion, Params(), TARGETS)
    p0, p1 = a[:3, 3], b[:3, 3]
    worst = 0.0
    while not h.done:
        layer.tick()
        p = (np.linalg.inv(cell.axes.body_pose("turn")) @ cell.flange_pose() @ tool)[:3, 3]
        u = float(np.clip(np.dot(p - p0, p1 - p0) / np.dot(p1 - p0, p1 - p0), 0.0, 1.0))
        worst = max(worst, float(np.linalg.norm(p - (p0 + u * (p1 - p0)))))
    layer.run_for(0.3)
    values = cell.axes.values()
    return {"dev_mm": 1000.0 * worst, "duration_s": h.end_time_s - h.start_time_s,
            "turn_error_mrad": 1000.0 * abs(values["turn"] - TARGETS["turn"]),
            "track_error_mm": 1000.0 * abs(values["track"] - TARGETS["track"])}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plant", default="realistic", choices=SIMULATED_PLANTS)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--whole-periods", action="store_true",
                        help="elastic gears: every move from rest averaged over the gears' whole periods")
    args = parser.parse_args()
    if args.whole_periods and args.plant != "elastic-gears":
        parser.error("--whole-periods is for --plant elastic-gears")
    scaled = False if args.whole_periods else None
    with_lead = run(args.plant, args.seed, lead=True, scaled_averaging=scaled)
    without = run(args.plant, args.seed, lead=False, scaled_averaging=scaled)
    limit_s = shortest_time_s(TARGETS["turn"], external_axes_of(load_world(CELL)).limits["turn"])
    print(f"plant={args.plant}")
    if args.plant == "elastic-gears":
        print(f"scaled_averaging={not args.whole_periods}")
    print(f"coordinated_tcp_dev_mm={with_lead['dev_mm']:.3f}")
    print(f"no_lead_tcp_dev_mm={without['dev_mm']:.3f}")
    print(f"duration_s={with_lead['duration_s']:.3f}")
    print(f"duration_over_turn_limit={with_lead['duration_s'] / limit_s:.3f}")
    print(f"turn_final_error_mrad={with_lead['turn_error_mrad']:.4f}")
    print(f"track_final_error_mm={with_lead['track_error_mm']:.4f}")


if __name__ == "__main__":
    main()
