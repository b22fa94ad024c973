"""The compiled IK tracking along Cartesian paths gives the joint samples the Python tracking (its reference) gives."""

from __future__ import annotations

import numpy as np
import pytest

from orc_rpl.errors import Unreachable
from orc_rpl.motion import CartesianMotion, Params, make_virtual_motion_layer
from orc_rpl.motion.paths import circle_poses, line_poses
from orc_rpl.plant import compiled
from orc_rpl.robot import load_robot
from orc_rpl.world.pose import Pose

pytestmark = [pytest.mark.sim, pytest.mark.skipif(not compiled.AVAILABLE, reason="no kernels to compare: numba is not installed or ORC_RPL_NO_JIT=1")]


def _both(kin, poses: np.ndarray, q0: np.ndarray, tool: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:  # type: ignore[no-untyped-def]
    kin.compiled_tracking = False
    reference = kin.ik_along(poses, q0, tool, "test path")
    kin.compiled_tracking = True
    return reference, kin.ik_along(poses, q0, tool, "test path")


@pytest.mark.parametrize("robot", ["irb2400", "ur5e"])
def test_lines_and_arcs_with_and_without_a_tool_give_the_reference_samples(robot: str) -> None:
    layer = make_virtual_motion_layer(robot, backend="kinematic")
    kin = layer.kin
    assert kin._compiled_chain(), "six revolute axes in a chain: the compiled tracking applies"
    q0 = np.array(kin.arm.home_q) + np.array([0.1, 0.05, -0.05, 0.2, 0.1, -0.3])
    tool = np.eye(4)
    tool[:3, :3] = Pose(0, 0, 0, 0.2, 0.1, 0.3).matrix()[:3, :3]
    tool[:3, 3] = [0.01, 0.02, 0.15]
    worst, samples = 0.0, 0
    for t in (None, tool):
        start = kin.fk(q0, t)
        for dx, dy, dz in [(0.0, 0.2, -0.1), (-0.15, -0.1, -0.15), (0.05, 0.1, 0.05)]:
            end = start.copy()
            end[:3, 3] += (dx, dy, dz)
            end[:3, :3] = Pose(0, 0, 0, 0.3, -0.2, 0.1).matrix()[:3, :3] @ start[:3, :3]
            via = start.copy()
            via[:3, 3] += (0.5 * dx + 0.05, 0.5 * dy - 0.05, 0.5 * dz)
            for poses in (line_poses(start, end), circle_poses(start, via, end)):
                reference, got = _both(kin, poses, q0, t)
                worst = max(worst, float(np.max(np.abs(got - reference))))
                samples += len(poses)
                # and the compiled samples put the TCP where the poses are
                for q, pose in zip(got[1:], poses[1:]):
                    assert np.allclose(kin.fk(q, t), pose, atol=1e-9)
    assert samples > 100
    assert worst <= 1e-9, worst


def test_a_path_through_a_flip_fails_the_same_way_compiled() -> None:
    """A sample the Newton steps cannot settle goes to the full IK as in the reference: the same error, the same place."""
    layer = make_virtual_motion_layer("irb2400", backend="kinematic")
    kin = layer.kin
    arm = load_robot("irb2400")
    q0 = np.array(arm.home_q)
    start = kin.fk(q0)
    end = start.copy()
    end[:3, 3] = [0.05, 0.0, start[2, 3]]  # straight over the base axis: a wrist/shoulder singularity on the way
    messages = []
    for on in (False, True):
        kin.compiled_tracking = on
        with pytest.raises(Unreachable) as caught:
            kin.ik_along(line_poses(start, end), q0, None, "linear motion")
        messages.append(str(caught.value))
    assert messages[0] == messages[1]


def test_lmoves_on_the_kinematic_robot_end_where_the_reference_ends() -> None:
    ends = []
    for on in (False, True):
        layer = make_virtual_motion_layer("irb2400", backend="kinematic")
        layer.kin.compiled_tracking = on
        home = Pose.from_matrix(layer.fk(layer.kin.arm.home_q))
        for dy in (0.3, -0.2):
            target = Pose(home.x - 0.1, home.y + dy, home.z - 0.2, home.a, home.b, home.c)
            layer.wait(layer.move(CartesianMotion(target), Params()))
        ends.append(layer.current_q())
    assert np.max(np.abs(ends[0] - ends[1])) <= 1e-9
