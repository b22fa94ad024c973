"""Clearance: distances from a robot's moving links to the fixed objects of any compiled MuJoCo model."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from orc_rpl.plant.clearance import ClearanceMeter, nearest_along, nearest_in_default_cell, robot_root

#: A one-joint "robot" (a 1 m arm of radius 0.05 m turning about z at 0.5 m height) beside a box and on a floor.
SCENE = """
<mujoco>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1"/>
    <geom name="block" type="box" pos="1.5 0 0.5" size="0.2 0.2 0.2"/>
    <body name="robot/base" pos="0 0 0">
      <geom name="pedestal" type="cylinder" size="0.1 0.25" pos="0 0 0.25"/>
      <body name="robot/link1" pos="0 0 0.5">
        <joint name="robot/j1" type="hinge" axis="0 0 1"/>
        <geom name="arm" type="capsule" fromto="0 0 0 1 0 0" size="0.05"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.fixture
def scene() -> tuple[mujoco.MjModel, mujoco.MjData]:
    model = mujoco.MjModel.from_xml_string(SCENE)
    return model, mujoco.MjData(model)


def _at(model: mujoco.MjModel, data: mujoco.MjData, angle_rad: float) -> None:
    data.qpos[0] = angle_rad
    mujoco.mj_kinematics(model, data)


def test_the_distance_is_from_the_moving_link_to_the_nearest_fixed_object(scene) -> None:
    model, data = scene
    meter = ClearanceMeter(model, data, robot_root(model), distmax_m=2.0)
    _at(model, data, 0.0)  # arm tip (radius included) at x = 1.05; the block's face at x = 1.3
    approach = meter.measure()
    assert approach is not None
    assert approach.distance_m == pytest.approx(0.25, abs=1e-6), "capsule end to box face along x"
    assert (approach.robot_geom, approach.obstacle_geom) == ("arm", "block")  # never the floor, never the pedestal


def test_nothing_within_distmax_gives_none_and_a_penetration_is_negative(scene) -> None:
    model, data = scene
    far = ClearanceMeter(model, data, robot_root(model), distmax_m=0.1)
    _at(model, data, math.pi)  # pointing away from the block
    assert far.measure() is None
    model.geom_pos[1][0] = 1.2  # move the block into the arm's reach: tip at 1.05 m, face at 1.0 m
    _at(model, data, 0.0)
    approach = far.measure()
    assert approach is not None and approach.distance_m == pytest.approx(-0.05, abs=1e-6)


def test_the_broad_phase_finds_what_every_pair_measured_finds(scene) -> None:
    model, data = scene
    meter = ClearanceMeter(model, data, robot_root(model), distmax_m=5.0)
    for angle in np.linspace(-math.pi, math.pi, 37):
        _at(model, data, float(angle))
        brute = min(mujoco.mj_geomDistance(model, data, int(a), int(b), 5.0, None) for a, b in meter.pairs)
        assert meter.measure().distance_m == pytest.approx(brute, abs=1e-9)


def test_the_nearest_approach_along_a_trajectory_is_where_the_arm_faces_the_block(scene) -> None:
    model, data = scene
    time_s = np.arange(0.0, 2.0, 0.004)
    q = (math.pi / 2 - math.pi / 2 * time_s).reshape(-1, 1)  # from 90 deg to -90 deg through 0 at t = 1 s
    approach = nearest_along(model, data, [0], time_s, q, rate_hz=50.0)
    assert approach is not None and approach.time_s == pytest.approx(1.0, abs=0.02)
    assert approach.distance_m == pytest.approx(0.25, abs=1e-3)


@pytest.mark.sim
def test_the_default_cell_measures_the_robot_against_its_table() -> None:
    q_home = np.radians([[0, 0, 30, 0, 60, 0]])
    approach = nearest_in_default_cell("irb2400", np.array([0.0]), q_home)
    assert approach is not None and approach.obstacle_geom.startswith("table")
    assert 0.0 < approach.distance_m < 0.5
