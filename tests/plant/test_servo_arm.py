"""The realistic SO-101: bus servos whose own position loops droop, with gear play, 12-bit encoders and warm windings."""

from __future__ import annotations

import math

import numpy as np
import pytest

from orc_rpl.errors import UsageError
from orc_rpl.executive.cell_robot import CellRobot
from orc_rpl.motion import JointMotion, make_virtual_motion_layer
from orc_rpl.plant.servo_arm import ServoArmCell
from orc_rpl.robot.plants import default_plant
from orc_rpl.robot.servo_plants import SERVO_PLANTS

pytestmark = pytest.mark.sim


def held(cell: ServoArmCell, seconds: float) -> None:
    for _ in range(round(seconds / cell.timestep_s)):
        cell.step_servos()


def test_the_so101_runs_on_its_realistic_plant_by_default() -> None:
    assert default_plant("so101") == "realistic"
    layer = make_virtual_motion_layer("so101")
    assert isinstance(layer.backend.cell, ServoArmCell)
    assert layer.backend.measures_torque is False and layer.path_velocity_control is False


def test_the_servos_own_loops_droop_under_gravity_by_what_their_gain_gives() -> None:
    cell = ServoArmCell("so101")
    spec = cell.plant
    goal = cell.goal_count.copy()
    held(cell, 0.5)
    error = goal - cell.counts
    # the shoulder and elbow hold the arm's weight: load / (stall torque x gain) counts, within the dead zone
    load_nm = np.abs(cell.duty * spec.stall_torque_nm)
    for joint in (1, 2):
        assert abs(error[joint]) >= 1
        assert abs(abs(error[joint]) - spec.droop_counts(load_nm[joint])) <= spec.deadband_counts + 0.5
    # the encoder reads whole counts of 4096 a turn
    np.testing.assert_allclose(cell.q / spec.rad_per_count, np.rint(cell.q / spec.rad_per_count), atol=1e-9)


def test_gravity_takes_up_the_gear_play_and_the_output_is_what_the_encoder_sees() -> None:
    cell = ServoArmCell("so101")
    play = cell.true_q - cell._data.qpos[cell._qpos]
    half = SERVO_PLANTS["so101"].backlash_rad / 2
    assert np.all(np.abs(play) <= half * 1.05)
    assert abs(abs(play[1]) - half) < 0.1 * half  # the shoulder rests on one side of its play
    assert np.all(np.abs(cell.true_q - cell.q) <= 0.5 * cell.plant.rad_per_count + 1e-12)


def test_a_loaded_servo_warms_up_and_a_limp_one_rests_on_its_gearbox() -> None:
    cell = ServoArmCell("so101")
    cold = cell.temperature_c.copy()
    cell.set_payload(0.3)  # a heavy part: the shoulder works hard
    held(cell, 20.0)
    assert cell.temperature_c[1] > cold[1] and cell.temperature_c[0] == cold[0]
    cell.set_payload(0.0)
    cell.set_torque([False] * 5)
    before = cell.q
    held(cell, 1.0)
    # back-driving a 1:345 gearbox takes more than the unloaded arm's weight: it stays within its play
    assert np.all(np.abs(cell.q - before) <= SERVO_PLANTS["so101"].backlash_rad + cell.plant.rad_per_count)


def test_a_servo_arm_takes_goals_not_torques() -> None:
    with pytest.raises(UsageError, match="goal positions"):
        ServoArmCell("so101").step(np.zeros(5))
    with pytest.raises(UsageError, match="not an arm on bus servos"):
        ServoArmCell("irb2400")


def test_a_fine_move_arrives_within_two_counts_once_the_host_corrects_the_droop() -> None:
    layer = make_virtual_motion_layer("so101")
    target = np.array(layer.kin.arm.home_q) + np.array([0.3, 0.2, -0.2, -0.1, 0.0])
    handle = layer.move(JointMotion(tuple(target)))
    layer.wait(handle)
    assert handle.settled
    rad = SERVO_PLANTS["so101"].rad_per_count
    assert np.all(np.abs(layer.backend.q() - target) < 2.0 * rad)


def test_the_simulated_gripper_servo_takes_its_time_and_closes_on_nothing() -> None:
    robot = CellRobot.virtual("so101")
    start = robot.time_s()
    assert robot.drive_gripper(6, math.radians(60), 0.5) is False
    opened = robot.time_s() - start
    # 58 degrees at the speed a 0.5 A cap allows (about 0.8 rad/s): over a second, under the 2 s wait
    assert 1.0 < opened < 2.0, opened
    assert robot.drive_gripper(6, math.radians(2), 0.5) is False
    with pytest.raises(UsageError, match="gripper is servo 6"):
        robot.drive_gripper(3, 0.0, 0.5)
