"""Short moves from rest on the IRB 2400's elastic gears: averaged over the periods of the modes that ring after them."""

from __future__ import annotations

import numpy as np
import pytest

from orc_rpl.motion import CartesianMotion, MotionLayer, Params, make_virtual_motion_layer
from orc_rpl.world.pose import Pose

#: The spot welding demo's gun (250 mm along the flange) over its first spot, and the step to the next (50 mm).
TOOL = Pose(0, 0, 0.25).matrix()
FIRST = Pose(0.9, -0.125, 0.6, 0, np.pi, 0)
PITCH_M = 0.05


def _speeds_after_short_move_mm_s(layer: MotionLayer) -> np.ndarray:
    """The controller's TCP speed every motion cycle from 40 to 120 ms after a 50 mm short move's reference ends."""
    layer.move(CartesianMotion(FIRST, tool=TOOL), Params())
    layer.run_for(2.0)                        # at rest over the first spot (a FINE move waits for the settling)
    nxt = Pose(FIRST.x, FIRST.y + PITCH_M, FIRST.z, 0, np.pi, 0)
    h = layer.short_move(CartesianMotion(nxt, tool=TOOL), Params())
    while h.t_end_s is None or layer.now_s() < h.t_end_s - 1e-9:   # until the reference has arrived
        layer.tick()
    tcp = []
    for _ in range(31):
        layer.tick()
        tcp.append(layer.tcp_pose(TOOL)[:3, 3])
    return np.linalg.norm(np.diff(tcp, axis=0), axis=1)[10:] / layer.dt_s * 1000.0


@pytest.mark.sim
def test_a_short_move_on_elastic_gears_stands_still_after_its_end() -> None:
    """WELDMOVE closes the gun on the TCP standing still (below 5 mm/s): measured at most 3.8 mm/s 40 to 120 ms after
    the end with the averaging, 14.9 mm/s without it (j1 and j2 ringing at about 16 Hz, j3 at 24 Hz)."""
    speeds = _speeds_after_short_move_mm_s(make_virtual_motion_layer("irb2400", plant="elastic-gears"))
    assert speeds.max() < 5.0, f"the TCP rings at up to {speeds.max():.1f} mm/s after the short move's end"


def test_an_averaged_short_move_ends_at_its_target_at_rest_and_its_speeds_match_its_positions() -> None:
    """Each joint's q, q' and q'' averaged alike: the servo's feed-forward is the derivative of its reference."""
    from orc_rpl.motion.short_move import ELASTIC_WINDOWS_S, ShortLimits, short_trajectory

    q0, q1 = np.zeros(6), np.array([0.05, -0.02, 0.03, 0.0, 0.04, -0.05])
    lim = ShortLimits(np.full(6, 2.0), np.full(6, 10.0), np.full(6, 400.0))
    plain = short_trajectory(q0, q0, q0, q1, lim, 0.004, 4, 1, lambda q: q[:3])
    traj = short_trajectory(q0, q0, q0, q1, lim, 0.004, 4, 1, lambda q: q[:3], windows_s=ELASTIC_WINDOWS_S)
    assert traj.kind == "short" and traj.exact_duration_s == pytest.approx(plain.exact_duration_s + 0.041 + 0.031)
    assert np.array_equal(traj.q_f[0], q0) and np.array_equal(traj.q_f[-1], q1) and not traj.qd_f[-1].any()
    step_s = 0.001
    assert np.abs(np.diff(traj.q_f, axis=0) / step_s - (traj.qd_f[1:] + traj.qd_f[:-1]) / 2).max() < 1e-3
