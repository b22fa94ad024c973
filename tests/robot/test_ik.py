"""Tests of inverse kinematics: round trips, nearest solution, unreachable targets and the workspace."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from orc_rpl.robot import load_robot, solve_ik
from orc_rpl.errors import Unreachable, UsageError
from orc_rpl.world.pose import matrix

DOWN_B = math.pi  # Pose(x, y, z, 0, 180 deg, 0): tool z pointing down


def _random_regular_configurations(arm, count: int, seed: int) -> list[np.ndarray]:
    """Configurations away from the wrist and elbow singularities, where 'the' solution is well defined."""
    rng = np.random.default_rng(seed)
    out: list[np.ndarray] = []
    while len(out) < count:
        q = rng.uniform(0.9 * arm.q_min, 0.9 * arm.q_max)
        if abs(math.sin(q[4])) > 0.2 and abs(math.sin(q[2])) > 0.2:
            out.append(q)
    return out


@pytest.mark.parametrize("name", ["irb2400", "ur5e"])
def test_fk_of_ik_round_trip_is_below_a_micrometre(name: str) -> None:
    arm = load_robot(name)
    tool = matrix(0.0, 0.0, 0.15)
    rng = np.random.default_rng(3)
    for q in _random_regular_configurations(arm, 25, seed=11):
        target = arm.fk(q, tool)
        seed = q + rng.normal(0.0, 0.2, arm.n_joints)
        solution = solve_ik(arm, target, seed, tool)
        reached = arm.fk(solution, tool)
        assert np.linalg.norm(reached[:3, 3] - target[:3, 3]) < 1e-6, "position round trip (m)"
        angle = math.acos(min(1.0, (np.trace(reached[:3, :3].T @ target[:3, :3]) - 1) / 2))
        assert angle < 1e-6, "rotation round trip (rad)"
        arm.check_limits(solution)
        # Nothing farther from the seed than the configuration the target came from.
        assert np.sum((solution - seed) ** 2) <= np.sum((q - seed) ** 2) + 1e-9


def test_ik_returns_the_wrist_solution_nearest_the_seed() -> None:
    arm = load_robot("irb2400")
    q_a = np.radians([10, 20, 10, 30, 50, 20])
    # The same flange pose with the wrist flipped: j4 + 180, -j5, j6 + 180.
    q_b = q_a + np.radians([0, 0, 0, -180, -100, -180])
    np.testing.assert_allclose(arm.fk(q_a), arm.fk(q_b), atol=1e-12)
    target = arm.fk(q_a)
    np.testing.assert_allclose(solve_ik(arm, target, q_a + 0.05), q_a, atol=1e-8)
    np.testing.assert_allclose(solve_ik(arm, target, q_b + 0.05), q_b, atol=1e-8)


def test_ik_takes_the_turn_of_j6_nearest_the_seed() -> None:
    arm = load_robot("irb2400")
    q = np.radians([0, 10, 20, 0, 40, 300])
    solution = solve_ik(arm, arm.fk(q), q + np.radians([0, 0, 0, 0, 0, 5]))
    assert solution[5] == pytest.approx(q[5], abs=1e-8)


def test_ik_is_deterministic() -> None:
    arm = load_robot("irb2400")
    target = matrix(0.9, 0.2, 0.6, 0.0, DOWN_B, 0.0)
    first = solve_ik(arm, target, np.zeros(6))
    assert np.array_equal(first, solve_ik(arm, target, np.zeros(6)))


def test_unreachable_target_says_where_and_by_how_much() -> None:
    arm = load_robot("irb2400")
    with pytest.raises(Unreachable, match=r"target \(2\.5000, 0\.0000, 1\.0000\) m, 2\.693 m from the base.*misses it by \d+\.\d mm"):
        solve_ik(arm, matrix(2.5, 0.0, 1.0, 0.0, DOWN_B, 0.0), arm.home_q)


def test_ik_rejects_a_target_that_is_not_a_transform() -> None:
    arm = load_robot("irb2400")
    with pytest.raises(UsageError, match="IK target"):
        solve_ik(arm, np.full((4, 4), math.nan), arm.home_q)


IRB_BOX = dict(x=(0.7, 1.2), y=(-0.4, 0.4), z=(0.4, 1.1))
UR_BOX = dict(x=(0.3, 0.6), y=(-0.3, 0.3), z=(0.05, 0.35))


def _grid(box: dict[str, tuple[float, float]]) -> list[tuple[float, float, float]]:
    corners = list(itertools.product(box["x"], box["y"], box["z"]))
    center = tuple(sum(v) / 2 for v in (box["x"], box["y"], box["z"]))
    return [*corners, center]


def _beyond_irb_envelope(x: float, y: float, z: float, tool_m: float) -> bool:
    """The IRB 2400 wrist centre reaches at most 1.450 m from the j2 axis (j3 stops at -60 deg)."""
    wrist = np.array([x, y, z + tool_m + 0.085])
    radial = math.hypot(wrist[0], wrist[1]) - 0.100
    return math.hypot(radial, wrist[2] - 0.615) > 1.4498


@pytest.mark.parametrize("tool_m", [0.0, 0.3])
def test_irb2400_reaches_the_table_workspace_pointing_down(tool_m: float) -> None:
    arm = load_robot("irb2400")
    tool = matrix(0.0, 0.0, tool_m)
    for x, y, z in _grid(IRB_BOX):
        target = matrix(x, y, z, 0.0, DOWN_B, 0.0)
        if _beyond_irb_envelope(x, y, z, tool_m):
            # Only the far top corners with the longest tool: 3.6 mm beyond the real robot's envelope.
            assert (x, z, tool_m) == (1.2, 1.1, 0.3)
            with pytest.raises(Unreachable, match="misses it by 3.6 mm"):
                solve_ik(arm, target, arm.home_q, tool)
            continue
        q = solve_ik(arm, target, arm.home_q, tool)
        assert np.abs(arm.fk(q, tool) - target).max() < 1e-6, f"pose ({x}, {y}, {z}) with tool {tool_m} m"


def test_irb2400_far_top_corner_is_reachable_with_a_290_mm_tool() -> None:
    arm = load_robot("irb2400")
    tool = matrix(0.0, 0.0, 0.29)
    q = solve_ik(arm, matrix(1.2, 0.4, 1.1, 0.0, DOWN_B, 0.0), arm.home_q, tool)
    arm.check_limits(q)


@pytest.mark.parametrize("tool_m", [0.0, 0.3])
def test_ur5e_reaches_its_smaller_workspace_pointing_down(tool_m: float) -> None:
    arm = load_robot("ur5e")
    tool = matrix(0.0, 0.0, tool_m)
    for x, y, z in _grid(UR_BOX):
        target = matrix(x, y, z, 0.0, DOWN_B, 0.0)
        q = solve_ik(arm, target, arm.home_q, tool)
        assert np.abs(arm.fk(q, tool) - target).max() < 1e-6, f"pose ({x}, {y}, {z}) with tool {tool_m} m"
