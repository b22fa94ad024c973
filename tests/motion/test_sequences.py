"""Sequences of moves: late arrivals, via points, stops inside blends, time functions, short-move stops, reset_ref."""

from __future__ import annotations

import math

import numpy as np

from orc_rpl.errors import PlanningError
from orc_rpl.motion import CartesianMotion, FunctionMotion, JointMotion, MotionLayer, MoveStatus, Params

from .motion_helpers import pose_here


def test_a_move_arriving_after_the_zone_entry_is_queued_not_blended(kinematic: MotionLayer) -> None:
    h1 = kinematic.move(CartesianMotion(pose_here(kinematic, 0.0, 0.3, 0.0)), Params(zone_m=0.05))
    kinematic.run_for(0.45)
    assert not h1.done
    h2 = kinematic.move(CartesianMotion(pose_here(kinematic, -0.2, 0.3, 0.0)))
    kinematic.wait(h2)
    assert h1.status is MoveStatus.READY and not h1.blended
    assert h2.start_time_s >= h1.end_time_s


def test_zone_via_points_are_blended_and_faster_than_fine_ones(kinematic: MotionLayer) -> None:
    q = kinematic.current_q()
    via = (tuple(q + np.array([0.4, 0, 0, 0, 0, 0])), tuple(q + np.array([0.4, 0.2, 0, 0, 0, 0])))
    times = []
    for zone in (0.0, 0.05):
        h = kinematic.move(JointMotion(tuple(q + 0.4), via), Params(zone_m=zone))
        assert len(h.plan.pieces) == (3 if zone == 0 else 1)
        kinematic.wait(h)
        times.append(h.end_time_s - h.start_time_s)
        kinematic.wait(kinematic.move(JointMotion(tuple(q))))
    assert times[1] < times[0] - 0.1, f"blended via points take {times[1]:.3f} s, FINE ones {times[0]:.3f} s"


def test_stop_inside_a_blend_cancels_the_moves_after_it(kinematic: MotionLayer) -> None:
    h1 = kinematic.move(CartesianMotion(pose_here(kinematic, 0.0, 0.3, 0.0)), Params(zone_m=0.1))
    h2 = kinematic.move(CartesianMotion(pose_here(kinematic, -0.3, 0.3, 0.0)), Params(zone_m=0.1))
    h3 = kinematic.move(CartesianMotion(pose_here(kinematic, -0.3, 0.0, 0.0)))
    while not h1.done:
        kinematic.tick()
    s = kinematic.stop_move()
    kinematic.run_until_idle()
    assert h1.status is MoveStatus.READY and h2.status is MoveStatus.ACT_STOPPED
    assert h2.stopped_s == s and 0.0 < s < 1.0
    assert h3.status is MoveStatus.ACT_STOPPED and h3.stopped_by == "cancelled"
    rest = kinematic.move(kinematic.path_left(h2, s))
    kinematic.wait(rest)
    assert np.linalg.norm(kinematic.tcp_pose()[:3, 3] - h2.motion.target.matrix()[:3, 3]) < 1e-6


def test_function_of_time_lasts_its_duration(kinematic: MotionLayer) -> None:
    p = pose_here(kinematic)
    h = kinematic.move(FunctionMotion(lambda t: p.x + 0.05 * math.sin(math.pi * t), p.y, p.z, p.a, p.b, p.c,
                                      variable="t", duration_s=2.0))
    kinematic.wait(h)
    assert abs((h.end_time_s - h.start_time_s) - 2.0) < 1e-9


def test_short_move_can_be_stopped(servo: MotionLayer) -> None:
    h = servo.short_move(JointMotion(tuple(servo.current_q() + 0.05)))
    servo.run_for(0.06)
    s = servo.stop_move()
    servo.run_until_idle()
    assert h.status is MoveStatus.ACT_STOPPED and 0.0 < s < 1.0
    assert float(np.max(np.abs(servo.current_q() - servo.reference_q()))) < 1e-3


def test_reset_ref_takes_the_measured_position(servo: MotionLayer) -> None:
    h = servo.move(JointMotion(tuple(servo.current_q() + 0.5)))
    servo.run_for(0.2)
    q = servo.reset_ref()
    assert h.status is MoveStatus.ACT_STOPPED and np.array_equal(servo.reference_q(), q)
    h = servo.move(JointMotion(tuple(servo.current_q() + 0.1)))
    servo.wait(h)
    assert h.status is MoveStatus.READY



def test_a_timing_failure_at_the_start_of_a_queued_move_is_a_fault_not_a_crash(kinematic: MotionLayer) -> None:
    start = kinematic.current_q()
    h1 = kinematic.move(JointMotion(tuple(start + 0.4)))
    h2 = kinematic.move(JointMotion(tuple(start)))
    h3 = kinematic.move(JointMotion(tuple(start + 0.1)))

    def fail(*args: object, **kwargs: object) -> None:
        raise PlanningError("no profile (test)")

    kinematic.planner.time = fail  # type: ignore[method-assign]
    kinematic.run_until_idle()
    assert h1.status is MoveStatus.READY
    assert h2.status is MoveStatus.FAULT and isinstance(h2.error, PlanningError)
    assert h3.status is MoveStatus.ACT_STOPPED and h3.stopped_by == "cancelled"
