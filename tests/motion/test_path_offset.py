"""A tracked move's path correction as the servo gets it (motion.path_offset): a step on rigid gears, a smooth
trajectory with its speed and acceleration on elastic gears."""

from __future__ import annotations

import numpy as np
import pytest

from orc_rpl.motion.path_offset import CORRECTION_OMEGA_RAD_S, PathOffset, correction_omega_rad_s


def test_rigid_gears_take_a_correction_as_a_step() -> None:
    assert correction_omega_rad_s(0.0) is None
    offset = PathOffset(2, None)
    offset.goal = np.array([0.001, -0.002])
    q, qd, qdd = offset.rows(4, 0.001)
    assert np.array_equal(q, np.tile([0.001, -0.002], (4, 1))) and not qd.any() and not qdd.any()


def test_on_elastic_gears_a_correction_is_reached_smoothly_with_its_speed_and_acceleration() -> None:
    assert correction_omega_rad_s(0.295) == CORRECTION_OMEGA_RAD_S
    offset = PathOffset(1, CORRECTION_OMEGA_RAD_S)
    offset.goal[0] = 0.001
    q, qd, qdd = (a[:, 0] for a in offset.rows(200, 0.001))
    assert q[-1] == pytest.approx(0.001, rel=1e-3)
    assert q.max() < 0.001 * (1 + 1e-4), "critically damped: no overshoot (the discretisation's own below 0.01 %)"
    # the servo's feed-forward gets the trajectory's own speed and acceleration
    assert np.allclose(np.diff(q) / 0.001, qd[1:], atol=0.002 * np.abs(qd).max())
    assert np.allclose(np.diff(qd) / 0.001, qdd[1:], atol=0.002 * np.abs(qdd).max())
    # no acceleration step where the goal changed (a torque step into the gears): it grows over the first steps,
    # to a quarter of the step two poles at the same rate would start with
    assert 0 < qdd[0] < qdd[1] < qdd[2]
    assert qdd.max() < 0.25 * CORRECTION_OMEGA_RAD_S ** 2 * 0.001
