"""Inverse kinematics of an arm with five axes (the SO-101): position exact, orientation as near as it can be."""

from __future__ import annotations

import math

import numpy as np
import pytest

from orc_rpl.errors import Unreachable
from orc_rpl.robot import load_robot, solve_ik
from orc_rpl.robot.ik import rotation_error


@pytest.fixture(scope="module")
def arm():  # noqa: ANN201
    return load_robot("so101")


def down(x: float, y: float, z: float, yaw: float = 0.0) -> np.ndarray:
    """The gripper pointing down, its x axis turned by yaw from world -x (POSE(x, y, z, yaw, 180deg, 0))."""
    c, s = math.cos(yaw), math.sin(yaw)
    t = np.eye(4)
    t[:3, :3] = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]) @ np.diag([-1.0, 1.0, -1.0])
    t[:3, 3] = (x, y, z)
    return t


def tilt(t: np.ndarray, angle: float, axis: int) -> np.ndarray:
    """t turned by `angle` about a world axis through its own origin."""
    r = np.eye(3)
    i, j = [k for k in range(3) if k != axis]
    r[i, i] = r[j, j] = math.cos(angle)
    r[i, j], r[j, i] = -math.sin(angle), math.sin(angle)
    out = t.copy()
    out[:3, :3] = r @ t[:3, :3]
    return out


@pytest.mark.parametrize("x", [0.15, 0.20, 0.25])
@pytest.mark.parametrize("y", [-0.10, 0.0, 0.10])
def test_every_pose_pointing_down_on_the_desk_is_reached_exactly(arm, x: float, y: float) -> None:  # noqa: ANN001
    for yaw in (0.0, 0.5):
        target = down(x, y, 0.02, yaw)
        t = arm.fk(solve_ik(arm, target, arm.home_q))
        assert np.abs(t[:3, 3] - target[:3, 3]).max() < 1e-9
        assert np.linalg.norm(rotation_error(target[:3, :3], t[:3, :3])) < 1e-9


def test_an_orientation_slightly_out_of_reach_is_taken_as_near_as_the_arm_can(arm) -> None:  # noqa: ANN001
    # leaning 0.3 deg sideways (out of the arm's vertical plane): no five-axis pose has it
    target = tilt(down(0.20, 0.0, 0.02), math.radians(0.3), axis=0)
    t = arm.fk(solve_ik(arm, target, arm.home_q))
    assert np.abs(t[:3, 3] - target[:3, 3]).max() < 1e-9, "the position is never traded for the orientation"
    miss = math.degrees(np.linalg.norm(rotation_error(target[:3, :3], t[:3, :3])))
    assert 0.2 < miss <= 0.3 + 1e-6


def test_a_tool_direction_the_arm_cannot_take_is_unreachable_with_its_angle_error(arm) -> None:  # noqa: ANN001
    target = tilt(down(0.20, 0.0, 0.02), math.radians(15.0), axis=0)
    with pytest.raises(Unreachable, match=r"misses it by 0\.0 mm and 1[45]\.\d\d deg"):
        solve_ik(arm, target, arm.home_q)


def test_a_position_out_of_reach_is_unreachable_with_its_distance(arm) -> None:  # noqa: ANN001
    with pytest.raises(Unreachable, match=r"target \(0\.6000, 0\.0000, 0\.1000\) m.*misses it by \d+\.\d mm"):
        solve_ik(arm, down(0.6, 0.0, 0.1), arm.home_q)
