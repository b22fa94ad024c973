"""Cartesian paths turn the tool as scipy's Slerp does (the reference of paths._slerp_poses), at any angle."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation, Slerp

from orc_rpl.motion.paths import _rotation_angle, _slerp_poses


def _pose(r: np.ndarray) -> np.ndarray:
    t = np.eye(4)
    t[:3, :3] = r
    return t


@pytest.mark.parametrize("kind", ["any", "near_half_turn", "tiny", "none"])
def test_slerp_orientations_and_the_angle_are_scipys(kind: str) -> None:
    rng = np.random.default_rng(7)
    u = np.linspace(0.0, 1.0, 41)
    worst_r = worst_a = 0.0
    for n in range(200):
        r0 = Rotation.random(random_state=n).as_matrix()
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        angle = {"any": rng.uniform(0.0, math.pi), "near_half_turn": math.pi - 10.0 ** -rng.uniform(1, 9),
                 "tiny": 10.0 ** -rng.uniform(3, 12), "none": 0.0}[kind]
        r1 = r0 @ Rotation.from_rotvec(axis * angle).as_matrix()
        reference = Slerp([0.0, 1.0], Rotation.from_matrix(np.stack([r0, r1])))(u).as_matrix()
        got = _slerp_poses(_pose(r0), _pose(r1), u)
        worst_r = max(worst_r, float(np.max(np.abs(got[:, :3, :3] - reference))))
        assert np.all(got[:, 3, :3] == 0.0) and np.all(got[:, :3, 3] == 0.0) and np.all(got[:, 3, 3] == 1.0)
        worst_a = max(worst_a, abs(_rotation_angle(_pose(r0), _pose(r1)) - Rotation.from_matrix(r0.T @ r1).magnitude()))
    assert worst_r <= 1e-13, worst_r
    assert worst_a <= 1e-13, worst_a
