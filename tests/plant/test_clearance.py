"""Clearance: distances from a robot's moving links to the fixed objects of any compiled MuJoCo model."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from orc_rpl.plant.clearance import (DISTMAX_M, TOLERANCE_FRACTION, TOLERANCE_M, ClearanceMeter, RunClearance,
                                     robot_root)
from orc_rpl.plant.sim import SimCell
from orc_rpl.plant.world_scene import cell_from_world
from orc_rpl.world import loads_world
from tests.plant.test_world_scene import WORLD

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


@pytest.mark.sim
def test_a_followed_run_is_exact_to_its_tolerance_per_motion_and_skips_samples() -> None:
    cell = SimCell(cell=cell_from_world(loads_world(WORLD)))
    follower = RunClearance(cell)
    brute = ClearanceMeter(follower.model, mujoco.MjData(follower.model), robot_root(follower.model), DISTMAX_M)
    joints = cell._qpos
    home = np.array(cell.description.robot_spec.home_q_rad)
    # two "motions": the wrist swings down towards the block, then back up
    down = [home + np.array([0, 0.6, 0.2, 0, 0.4, 0]) * f for f in np.linspace(0, 1, 200)]
    path = [("down", q) for q in down] + [("up", q) for q in down[::-1]]
    smallest: dict[str, float] = {}
    for i, (key, q) in enumerate(path):
        cell._data.qpos[joints] = q
        follower.sample(key, 0.004 * i)
        brute.data.qpos[:] = cell._data.qpos
        mujoco.mj_kinematics(brute.model, brute.data)
        exact = brute.measure()
        assert exact is not None
        smallest[key] = min(smallest.get(key, np.inf), exact.distance_m)
    for key in ("down", "up"):
        found = follower.nearest[key]
        assert found is not None and found.obstacle == "block"
        assert found.distance_m >= smallest[key] - 1e-9
        assert found.distance_m - smallest[key] <= max(TOLERANCE_M, TOLERANCE_FRACTION * smallest[key])
    assert follower.measured < follower.samples / 2, "far from its nearest so far, a sample is not measured"


def test_the_work_is_no_obstacle() -> None:
    follower = RunClearance(SimCell(cell=cell_from_world(loads_world(WORLD))))
    names = {mujoco.mj_id2name(follower.model, mujoco.mjtObj.mjOBJ_GEOM, int(b)) for b in follower.meter.pairs[:, 1]}
    assert "block" in names and "part" not in names
