"""Moving frames: a track under the robot, a two-axis positioner, a conveyor; their poses and their located errors."""

from __future__ import annotations

import math

import numpy as np
import pytest

from orc_rpl.errors import SourceError
from orc_rpl.world import WorldError, load_world, loads_world
from tests.world.test_roundtrip import WORLDS

CELL = next(p for p in WORLDS if p.stem == "positioner_cell")


def test_the_robot_rides_on_the_track_and_the_plate_turns_with_the_positioner() -> None:
    world = load_world(CELL)
    assert world.moving_frames() == ("track", "tilt", "turn")
    assert world.parent("robot") == "track" and world.children("track") == ("robot",)
    at_home = world.relative_pose("plate.seam_start", "robot")
    moved = world.with_axes({"track": 0.3})
    assert moved.relative_pose("plate.seam_start", "robot").x == pytest.approx(at_home.x - 0.3)
    turned = world.with_axes({"turn": math.pi / 2})
    start = turned.world_pose("plate.seam_start")  # (-100, 50) mm on the table, turned a quarter about z
    assert (start.x, start.y) == pytest.approx((1.0 - 0.05, -0.1))
    # relative to the plate nothing moved: the frame rides with it
    assert np.allclose(turned.relative_pose("plate.seam_start", "plate").matrix(),
                       world.relative_pose("plate.seam_start", "plate").matrix())
    tilted = world.with_axes({"tilt": math.pi / 2})
    assert tilted.world_pose("plate.seam_start").z == pytest.approx(0.45 + 0.05)


def test_an_axis_outside_its_range_or_an_axis_that_is_not_one_is_refused() -> None:
    world = load_world(CELL)
    with pytest.raises(WorldError, match=r"axis 'track': 600mm is outside its range 0mm..500mm"):
        world.with_axes({"track": 0.6})
    with pytest.raises(WorldError, match="'plate' is not a moving frame"):
        world.with_axes({"plate": 0.0})


def test_a_conveyor_is_a_moving_frame_with_a_speed() -> None:
    world = loads_world("world:\n  belt:\n    pose: [1m, 0, 0.5m, 0, 0, 0]\n"
                        "    axis: {joint: conveyor, direction: y, speed: -100mm/s}\n")
    belt = world.object("belt").axis
    assert belt is not None and belt.speed_si == pytest.approx(-0.1)
    assert world.with_axes({"belt": belt.speed_si * 2.0}).world_pose("belt").y == pytest.approx(-0.2)


BAD = {
    "unknown joint": ("    axis: {joint: slider, range: [0, 1m], speed: 1m/s, acceleration: 1m/s2}\n",
                      "3:19: unknown joint 'slider'"),
    "missing speed": ("    axis: {joint: rotary, range: [0, 1rad], acceleration: 1rad/s2}\n",
                      "3:11: a rotary axis needs 'speed'"),
    "wrong unit": ("    axis: {joint: rotary, range: [0, 1rad], speed: 1m/s, acceleration: 1rad/s2}\n",
                   "3:52: the axis' speed must be an angular velocity, got '1m/s'"),
    "bad direction": ("    axis: {joint: linear, direction: w, range: [0, 1m], speed: 1m/s, acceleration: 1m/s2}\n",
                      "3:38: an axis' direction is x, y or z"),
    "reversed range": ("    axis: {joint: linear, range: [1m, 0], speed: 1m/s, acceleration: 1m/s2}\n",
                       "3:34: an axis' range needs its lowest value first"),
    "conveyor range": ("    axis: {joint: conveyor, speed: 1m/s, range: [0, 1m]}\n",
                       "3:42: a conveyor has no 'range'"),
    "unknown key": ("    axis: {joint: conveyor, sped: 1m/s}\n", "3:29: unknown axis attribute 'sped'"),
    "home outside": ("    axis: {joint: linear, range: [0, 1m], speed: 1m/s, acceleration: 1m/s2, home: 2m}\n",
                     "3:83: the axis' home is outside its range"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_axis_declarations_are_reported_at_their_line_and_column(case: str) -> None:
    line, expected = BAD[case]
    with pytest.raises(SourceError) as info:
        loads_world("world:\n  slide:\n" + line, "cell.yaml")
    assert f"cell.yaml:{expected}" in str(info.value)


def test_the_robot_cannot_ride_on_an_unknown_object_or_on_itself() -> None:
    with pytest.raises(SourceError) as info:
        loads_world("robot:\n  model: irb2400\n  parent: trak\nworld:\n  track:\n    pose: [0, 0, 0, 0, 0, 0]\n", "cell.yaml")
    assert "cell.yaml:3:11: unknown parent 'trak' of the robot" in str(info.value)
    assert "did you mean 'track'?" in str(info.value)
    with pytest.raises(SourceError) as info:
        loads_world("robot:\n  model: irb2400\n  parent: holder\nworld:\n  holder:\n    parent: flange\n", "cell.yaml")
    assert "cell.yaml:3:11: the robot cannot ride on 'holder'" in str(info.value)
    with pytest.raises(SourceError) as info:
        loads_world("world:\n  slide:\n    parent: flange\n    axis: {joint: conveyor, speed: 1m/s}\n", "cell.yaml")
    assert "cell.yaml:4:5: 'slide' hangs on the robot" in str(info.value)
