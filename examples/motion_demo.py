"""Motion-core demo: joint, linear (blended) and circular moves on the virtual robot, recorded and plotted.

Run: python examples/motion_demo.py [--robot irb2400|ur5e] [--out motion_demo.png]
"""

from __future__ import annotations

import argparse

import numpy as np

from orc_rpl.motion import CartesianMotion, JointMotion, Params, make_virtual_motion_layer
from orc_rpl.world.pose import Pose


def main() -> None:
    ap = argparse.ArgumentParser(description="joint, linear and circular moves on the virtual robot")
    ap.add_argument("--robot", default="irb2400")
    ap.add_argument("--out", default="motion_demo.png")
    args = ap.parse_args()

    layer = make_virtual_motion_layer(args.robot, record=True)       # arm model + servo + MuJoCo + logger
    q0 = layer.current_q()
    p = Pose.from_matrix(layer.tcp_pose())                             # TCP at home
    reach = 0.25 if args.robot == "ur5e" else 0.4                      # keep the square inside the smaller arm's reach

    def at(dx: float, dy: float, dz: float) -> Pose:
        return Pose(p.x + dx, p.y + dy, p.z + dz, p.a, p.b, p.c)

    layer.wait(layer.move(JointMotion(tuple(q0 + np.array([0.4, 0.2, -0.1, 0.3, -0.2, 0.5])))))  # MOVE, FINE
    layer.wait(layer.move(JointMotion(tuple(q0))))                                                # back home
    # LMOVEs through two corners with a 3 cm zone: issued ahead, so the layer blends them
    layer.move(CartesianMotion(at(0.0, reach, -0.1)), Params(zone_m=0.03, speed_m_s=1.0))
    layer.wait_for_room(1)
    layer.move(CartesianMotion(at(-0.2, reach, -0.1)), Params(zone_m=0.03, speed_m_s=1.0))
    layer.wait_for_room(1)
    last = layer.move(CartesianMotion(at(-0.2, 0.0, -0.1)), Params(speed_m_s=1.0))              # FINE
    layer.wait(last)
    # CMOVE: a half circle through an auxiliary point
    circle = layer.move(CartesianMotion(at(-0.2, -reach, -0.1), "circular", via=at(-0.2 + reach / 2, -reach / 2, -0.1)))
    layer.wait(circle)

    err_mm = 1000 * np.linalg.norm(layer.tcp_pose()[:3, 3] - circle.motion.target.matrix()[:3, 3])
    png = layer.logger.recording().plot_png(args.out, signals=["q_ref", "tau"])
    print(f"{args.robot}: {layer.now_s():.3f} s of motion, final TCP error {err_mm:.3f} mm, plot {png}")


if __name__ == "__main__":
    main()
