"""TOPP-RA's passes made lean (motion/toppra_passes.py) give toppra's own profiles bit for bit, and its failures."""

from __future__ import annotations

import math

import numpy as np
import pytest

from orc_rpl.motion import CartesianMotion, JointMotion, MotionLayer, Params
from orc_rpl.motion import timing
from orc_rpl.motion.trajectory import SplinePath
from orc_rpl.world.pose import Pose

from .motion_helpers import pose_here


def _moves(layer: MotionLayer) -> list[tuple[object, Params]]:
    home = np.array(layer.kin.arm.home_q)
    here = pose_here(layer)
    return [
        (JointMotion(tuple(home + np.array([0.8, 0.3, -0.2, 0.5, -0.3, 1.0]))), Params()),
        (JointMotion(tuple(home + np.array([2.6, 0.2, -0.1, 0.5, 0.3, 1.0]))), Params(load_kg=10.0)),
        (CartesianMotion(Pose(here.x, here.y + 0.4, here.z - 0.2, here.a, here.b, here.c)), Params(speed_m_s=0.5)),
        (CartesianMotion(Pose(here.x - 0.2, here.y - 0.3, here.z - 0.3, here.a, here.b, here.c)), Params(accel_fraction=0.5)),
    ]


def _planned_paths(layer: MotionLayer) -> list[tuple[SplinePath, timing.TimingLimits]]:
    """The path and limits of each of `_moves`, planned from where the layer is."""
    out = []
    for motion, params in _moves(layer):
        plan = layer.planner.plan(1, motion, params, layer.current_q())
        assert plan is not None
        out.append((SplinePath(plan.pieces[0]), plan.limits))
    return out


def _both(path: SplinePath, limits: timing.TimingLimits, sd_start: float, points: int | None):  # type: ignore[no-untyped-def]
    return (timing.toppra_profile(path, limits, sd_start, 0.0, points, lean=False),
            timing.toppra_profile(path, limits, sd_start, 0.0, points, lean=True))


def test_the_lean_passes_give_toppras_profiles_bit_for_bit(kinematic: MotionLayer) -> None:
    compared = 0
    for path, limits in _planned_paths(kinematic):
        for points in (None, 300):
            for sd_start in (0.0, 0.2):
                reference, lean = _both(path, limits, sd_start, points)
                assert reference is not None and lean is not None
                assert np.array_equal(reference[0], lean[0]) and np.array_equal(reference[1], lean[1])
                compared += 1
    assert compared == 16


def test_an_uncontrollable_start_fails_in_both_and_a_start_just_above_the_set_is_retried_alike(kinematic: MotionLayer) -> None:
    motion, params = _moves(kinematic)[0]
    plan = kinematic.planner.plan(1, motion, params, kinematic.current_q())
    assert plan is not None
    path = SplinePath(plan.pieces[0])
    reference, lean = _both(path, plan.limits, 50.0, None)  # far faster than the path allows at its start
    assert reference is None and lean is None
    # the largest controllable start speed: a start a hair above it is retried at the set's edge (toppra_profile)
    toppra, geometric = timing._toppra()[:2]
    algo = toppra.algorithm.TOPPRA(timing.constraints(path, plan.limits), geometric(path),
                                   gridpoints=timing.grid_for(path), solver_wrapper="seidel")
    sets = algo.compute_controllable_sets(0.0, 0.0)
    edge = math.sqrt(float(sets[0, 1]))
    for sd_start in (0.5 * edge, edge, 1.01 * edge):
        reference, lean = _both(path, plan.limits, sd_start, None)
        assert reference is not None and lean is not None
        assert np.array_equal(reference[1], lean[1])
        assert lean[1][0] <= edge * (1 + 1e-12)


@pytest.mark.parametrize("sd_start", [0.0, 0.5])
def test_the_timed_trajectories_are_the_same(kinematic: MotionLayer, sd_start: float) -> None:
    motion, params = _moves(kinematic)[2]
    plan = kinematic.planner.plan(1, motion, params, kinematic.current_q())
    assert plan is not None
    path = SplinePath(plan.pieces[0])
    grid_sd = _both(path, plan.limits, sd_start, None)
    assert grid_sd[0] is not None and grid_sd[1] is not None
    assert np.array_equal(grid_sd[0][1], grid_sd[1][1])
