"""TOPP-RA's passes compiled (motion/toppra_kernels.py) give the lean Python passes' profiles on toppra's own
seidel solver (their reference) bit for bit: the controllable sets, the forward pass, its failures and retries."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterator

import numpy as np
import pytest

from orc_rpl.motion import MotionLayer, timing, toppra_passes
from orc_rpl.motion.trajectory import SplinePath
from orc_rpl.plant import compiled

from .test_toppra_passes import _moves, _planned_paths

pytestmark = pytest.mark.skipif(not compiled.AVAILABLE, reason="numba is not installed: no compiled passes")


@pytest.fixture
def switch() -> Iterator[None]:
    before = toppra_passes.COMPILED_PASSES
    yield
    toppra_passes.COMPILED_PASSES = before


def _algorithm(path: SplinePath, limits: timing.TimingLimits, compiled_passes: bool, points: int | None = None):  # type: ignore[no-untyped-def]
    toppra, geometric = timing._toppra()[:2]
    toppra_passes.COMPILED_PASSES = compiled_passes
    return timing._toppra()[5](timing.constraints(path, limits), geometric(path), gridpoints=timing.grid_for(path, points),
                               solver_wrapper="seidel")


def _profiles(path: SplinePath, limits: timing.TimingLimits, sd_start: float, points: int | None):  # type: ignore[no-untyped-def]
    out = []
    for compiled_passes in (False, True):
        toppra_passes.COMPILED_PASSES = compiled_passes
        out.append(timing.toppra_profile(path, limits, sd_start, 0.0, points))
    return out


def test_the_compiled_passes_run_without_toppras_wrapper_and_the_switch_turns_them_off(kinematic: MotionLayer,
                                                                                      switch: None) -> None:
    motion, params = _moves(kinematic)[0]
    plan = kinematic.planner.plan(1, motion, params, kinematic.current_q())
    path = SplinePath(plan.pieces[0])
    assert isinstance(_algorithm(path, plan.limits, True).solver_wrapper, toppra_passes.CompiledSeidel)
    assert not isinstance(_algorithm(path, plan.limits, False).solver_wrapper, toppra_passes.CompiledSeidel)


def test_the_compiled_passes_give_the_python_passes_profiles_bit_for_bit(kinematic: MotionLayer, switch: None) -> None:
    compared = 0
    for path, limits in _planned_paths(kinematic):
        for points in (None, 300):
            reference_sets = _algorithm(path, limits, False, points).compute_controllable_sets(0.0, 0.0)
            sets = _algorithm(path, limits, True, points).compute_controllable_sets(0.0, 0.0)
            assert np.array_equal(reference_sets, sets)
            for sd_start in (0.0, 0.2):
                reference, ours = _profiles(path, limits, sd_start, points)
                assert reference is not None and ours is not None
                assert np.array_equal(reference[0], ours[0]) and np.array_equal(reference[1], ours[1])
                compared += 1
    assert compared == 16


def test_failures_and_the_retry_at_the_sets_edge_are_the_python_passes(kinematic: MotionLayer, switch: None) -> None:
    motion, params = _moves(kinematic)[1]
    plan = kinematic.planner.plan(1, motion, params, kinematic.current_q())
    path = SplinePath(plan.pieces[0])
    assert _profiles(path, plan.limits, 50.0, None) == [None, None]   # far faster than the path allows at its start
    edge = math.sqrt(float(_algorithm(path, plan.limits, False).compute_controllable_sets(0.0, 0.0)[0, 1]))
    for sd_start in (0.5 * edge, edge, 1.01 * edge):
        reference, ours = _profiles(path, plan.limits, sd_start, None)
        assert reference is not None and ours is not None
        assert np.array_equal(reference[1], ours[1])


def test_a_path_with_no_controllable_set_fails_alike(kinematic: MotionLayer, switch: None) -> None:
    motion, params = _moves(kinematic)[0]
    plan = kinematic.planner.plan(1, motion, params, kinematic.current_q())
    path = SplinePath(plan.pieces[0])
    limits = plan.limits
    # a torque limit below the weight's torque: no speed is feasible anywhere, the sets end in NaN at once
    assert limits.tau_max is not None
    weak = dataclasses.replace(limits, tau_max=limits.tau_max * 1e-3)
    reference = _algorithm(path, weak, False).compute_controllable_sets(0.0, 0.0)
    ours = _algorithm(path, weak, True).compute_controllable_sets(0.0, 0.0)
    assert np.isnan(reference).any()
    assert np.array_equal(reference, ours, equal_nan=True)
    assert _profiles(path, weak, 0.0, None) == [None, None]
