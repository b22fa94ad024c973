"""The controller's gearbox warm-up estimate: friction falls from its cold value as the joints work, as the plant's does."""

from __future__ import annotations

import math

import numpy as np
import pytest

from orc_rpl.application.runtime import MotionRequest, run_to_end
from orc_rpl.errors import UsageError
from orc_rpl.executive.cell_robot import CellRobot
from orc_rpl.motion.gear_friction import CHANGE_SPREAD, GearFriction, change_since
from orc_rpl.world.pose import Pose


def estimate(**changes: object) -> GearFriction:
    args: dict[str, object] = dict(coulomb_nm=(40.0, 4.0), viscous_nm_s=(60.0, 3.0), gear_rth_k_w=(0.5, 4.0),
                                   gear_time_constant_s=1200.0, cold_friction_factor=2.0, warm_rise_k=6.0,
                                   motor_heat_share=0.3, torque_per_amp_nm_a=(40.0, 8.0), resistance_ohm=(1.2, 4.0),
                                   tempco_1_k=0.00393, ambient_c=20.0, period_s=0.004)
    args.update(changes)
    return GearFriction(**args)  # type: ignore[arg-type]


def test_a_cold_start_has_the_cold_friction_and_a_warm_robot_the_nominal() -> None:
    gears = estimate()
    assert gears.friction_nm()[0] == pytest.approx([80.0, 8.0])
    gears.warm_up(60.0)
    assert gears.friction_nm()[0] == pytest.approx([40.0, 4.0], rel=1e-4)


def test_working_joints_warm_and_their_friction_falls_by_a_change_with_its_spread() -> None:
    gears = estimate()
    before = gears.state(0.0)
    for _ in range(2500):  # 10 s: joint 1 turns at 1 rad/s with 200 N m, joint 2 stands still
        gears.update(np.array([200.0, 0.0]), np.array([1.0, 0.0]))
    change = change_since(before, gears.state(10.0))
    assert change.coulomb_nm[0] < -0.5 and change.coulomb_nm[1] == 0.0
    assert change.viscous_nm_s[0] == pytest.approx(1.5 * change.coulomb_nm[0])  # the same factor on both
    assert change.coulomb_sigma_nm[0] == pytest.approx(CHANGE_SPREAD * -change.coulomb_nm[0])
    # the friction needed at a speed: Coulomb with the sign of the motion (sharp), viscous with the speed
    coulomb, viscous = gears.friction_nm()
    assert gears.torque_nm(np.array([-0.5, 0.0])) == pytest.approx([-coulomb[0] - 0.5 * viscous[0], 0.0], rel=1e-6)


def test_bad_figures_are_refused() -> None:
    with pytest.raises(UsageError, match="cold factor"):
        estimate(cold_friction_factor=0.5)
    with pytest.raises(UsageError, match="per joint"):
        estimate(gear_rth_k_w=(0.5,))


@pytest.mark.sim
def test_the_realistic_cell_s_estimate_follows_its_plant_s_friction() -> None:
    robot = CellRobot.virtual(plant="realistic")
    cell = robot.layer.backend.loop.cell  # type: ignore[attr-defined]
    for target in (Pose(0.9, 0.0, 0.9, 0.0, math.pi, 0.0), Pose(0.8, -0.3, 0.45, 0.0, math.pi, 0.0)) * 3:
        run_to_end(robot, MotionRequest("MOVE", "joint", target), 30.0, "a move")
    state = robot.friction_state()
    # the plant's warm friction is 1.1 times the nominal: the estimate's factor, not its level, follows the plant's
    assert np.array(state.coulomb_nm[:3]) / np.array(cell.friction_nm()[0][:3]) == pytest.approx(1 / 1.1, rel=0.01)
    assert robot.layer.gear_friction.rise_k[:3] == pytest.approx(cell.gear_rise_k[:3], rel=0.1)  # type: ignore[attr-defined]
    assert CellRobot.virtual(plant="ideal").friction_state() is None
