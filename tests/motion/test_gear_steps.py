"""Elastic gears under state feedback: each move from rest averaged over as much of the windows as it twists the gears, or the whole."""

from __future__ import annotations

import numpy as np
import pytest

from orc_rpl.motion import JointMotion, MotionLayer, Params, make_virtual_motion_layer
from orc_rpl.errors import UsageError
from orc_rpl.motion.gear_steps import GearSteps


def test_the_windows_are_the_share_of_the_full_step_never_shorter_than_the_least() -> None:
    steps = GearSteps((1.0,), (1e-5,), full_step_rad=4e-3, least_s=0.02)
    assert steps.windows((0.16, 0.12), 8e-3) == (0.16, 0.12)
    assert steps.windows((0.16, 0.12), 2e-3) == pytest.approx((0.08, 0.06))
    assert steps.windows((0.16, 0.12), 1e-4) == (0.02, 0.02)


def _extra_s(layer: MotionLayer, motion: JointMotion, params: Params) -> float:
    """How much longer the move from rest lasts for its averaging (over its unaveraged duration)."""
    planner = layer.planner
    plan = planner.plan(1, motion, params, np.array(layer.reference_q()))
    assert plan is not None
    averaged = planner.time(plan.pieces[0], plan.limits).exact_duration_s
    windows, planner.smoothing_s = planner.smoothing_s, ()
    try:
        return averaged - planner.time(plan.pieces[0], plan.limits).exact_duration_s
    finally:
        planner.smoothing_s = windows


@pytest.fixture(scope="module")
def elastic() -> MotionLayer:
    return make_virtual_motion_layer("irb2400", plant="elastic-gears", scaled_averaging=True)


def test_a_heavy_fast_move_gets_the_whole_windows_a_gentle_one_a_share(elastic: MotionLayer) -> None:
    whole = sum(elastic.smoothing_s)
    heavy = _extra_s(elastic, JointMotion(tuple(np.radians((150, 70, -20, 0, -60, 90)))), Params(load_kg=10.0))
    fast = _extra_s(elastic, JointMotion((0.8, -0.2, 0.3, 0.5, 0.6, -0.7)), Params())
    gentle = _extra_s(elastic, JointMotion((0.8, -0.2, 0.3, 0.5, 0.6, -0.7)), Params(accel_fraction=0.25))
    assert heavy == pytest.approx(whole, abs=0.005)   # bench_arm_control's second move: 4.5 mrad of twist
    assert 0.04 <= gentle < fast < whole


def test_elastic_gears_scale_by_default_and_give_every_move_the_whole_windows_when_asked() -> None:
    gentle = (JointMotion((0.8, -0.2, 0.3, 0.5, 0.6, -0.7)), Params(accel_fraction=0.25))
    whole = make_virtual_motion_layer("irb2400", plant="elastic-gears", scaled_averaging=False)
    assert _extra_s(whole, *gentle) == pytest.approx(sum(whole.smoothing_s), abs=0.005)
    assert _extra_s(make_virtual_motion_layer("irb2400", plant="elastic-gears"), *gentle) < 0.15


def test_scaled_averaging_is_for_the_state_feedback() -> None:
    with pytest.raises(UsageError, match="scaled_averaging is for the elastic gears' state feedback"):
        make_virtual_motion_layer("irb2400", elastic=True, gear_feedforward=True, scaled_averaging=True)


def test_a_move_asking_for_whole_averaging_gets_the_whole_windows_where_others_get_a_share() -> None:
    layer = make_virtual_motion_layer("irb2400", plant="elastic-gears")   # scaled: the default
    start, target = tuple(layer.reference_q()), JointMotion((0.8, -0.2, 0.3, 0.5, 0.6, -0.7))

    def duration_s(params: Params) -> float:
        there = layer.move(target, params)
        layer.wait(there)
        layer.wait(layer.move(JointMotion(start), Params(accel_fraction=0.25)))
        assert there.start_time_s is not None and there.t_end_s is not None
        return there.t_end_s - there.start_time_s

    scaled = duration_s(Params(accel_fraction=0.25))
    whole = duration_s(Params(accel_fraction=0.25, whole_averaging=True))   # IDENTMOVE's lift, TRACKMOVE: a quiet start
    gentle = _extra_s(layer, target, Params(accel_fraction=0.25))
    assert whole - scaled == pytest.approx(sum(layer.smoothing_s) - gentle, abs=0.005)
    assert whole - scaled > 0.15
