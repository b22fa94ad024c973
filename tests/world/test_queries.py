"""Queries of the world tree: names, world poses by composition, on-line frames, tool chains, attributes."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from orc_rpl.syntax.units import Quantity
from orc_rpl.world import Pose, PathAttribute, Position, WorldError, load_world
from orc_rpl.world.pose import matrix

WORLDS = Path(__file__).parents[2] / "worlds"
TOL = 1e-12  # composition of a few exact transforms: only rounding error is allowed


@pytest.fixture(scope="module")
def thesis():
    return load_world(WORLDS / "cell_thesis.yaml")


def test_world_pose_is_the_product_of_poses_up_the_tree(thesis) -> None:
    expected = (matrix(1.0, 0, 0.6)                          # table
                @ matrix(0, 0.1, 0, math.pi / 2)              # fixture, turned about z
                @ matrix(0, 0, 0.02)                          # base_plate
                @ matrix(0.05, -0.04, 0.06, -math.pi / 2, math.pi, 0))  # pos1
    got = thesis.world_pose("base_plate.pos1").matrix()
    assert np.allclose(got, expected, atol=TOL), "world pose must be table*fixture*base_plate*pos1"
    assert np.allclose(got[:3, 3], [1.04, 0.15, 0.68], atol=TOL)


def test_relative_pose_to_an_ancestor_and_back(thesis) -> None:
    rel = thesis.relative_pose("base_plate.pos2", "table")
    assert rel.frame == "table"
    back = thesis.world_pose("table").compose(rel)
    assert np.allclose(back.matrix(), thesis.world_pose("base_plate.pos2").matrix(), atol=TOL)


def test_relative_pose_between_unrelated_objects(thesis) -> None:
    rel = thesis.relative_pose("pos3", "base_plate")
    want = np.linalg.inv(thesis.world_pose("base_plate").matrix()) @ thesis.world_pose("pos3").matrix()
    assert np.allclose(rel.matrix(), want, atol=TOL)


def test_online_frame_of_positions_and_objects(thesis) -> None:
    assert thesis.online_frame_of("base_plate.pos1") == "base_plate"
    assert thesis.online_frame_of("base_plate") == "world"   # the frame itself is placed in world
    assert thesis.online_frame_of("pos0") == "world"
    pose = thesis.online_pose("base_plate.pos1")
    assert pose.frame == "base_plate"
    assert np.allclose([pose.x, pose.y, pose.z], [0.05, -0.04, 0.06], atol=TOL)


def test_nested_online_frames_list_parents_first(thesis) -> None:
    world = thesis.with_object("clamp", "base_plate", Pose(0, 0.2, 0, frame="base_plate"), online_frame=True)
    world = world.with_frame("clamp", "c1", Pose(0, 0, 0.05, 0, math.pi, 0, frame="clamp"))
    frames = world.online_frames()
    assert [(f.name, f.parent) for f in frames] == [("base_plate", "world"), ("clamp", "base_plate")]
    assert np.allclose([frames[1].pose.x, frames[1].pose.y], [0, 0.2], atol=TOL)
    assert world.online_frame_of("clamp.c1") == "clamp"
    assert world.online_frame_of("clamp") == "base_plate"


def test_tool_chain_collapses_to_one_flange_pose(thesis) -> None:
    assert thesis.tool_chain("grinder") == ("holder", "grinder")
    tcp = thesis.tool_pose("grinder")
    assert tcp.frame == "flange"
    assert np.allclose(tcp.matrix(), matrix(0, 0, 0.06) @ matrix(0.02, 0, 0.12), atol=TOL), "Holder*Grinder"
    with pytest.raises(WorldError, match="not mounted on the flange"):
        thesis.tool_chain("table")


def test_world_pose_below_the_flange_needs_the_run_time_flange_pose(thesis) -> None:
    with pytest.raises(WorldError, match="run time"):
        thesis.world_pose("grinder")
    flange = Pose(0.9, 0.0, 1.0, 0, math.pi, 0, frame="robot")
    tcp = thesis.with_flange(flange).world_pose("grinder")
    assert np.allclose(tcp.matrix(), flange.matrix() @ thesis.tool_pose("grinder").matrix(), atol=TOL)


def test_lookup_by_dotted_name() -> None:
    world = load_world(WORLDS / "spot_welding.yaml")
    assert isinstance(world.lookup("door.s3"), Position)
    assert isinstance(world.lookup("door.spots"), PathAttribute)
    assert world.lookup("door.spots[3]") == world.lookup("door.s3").pose
    assert world.lookup("door.next_spot") == 1
    with pytest.raises(WorldError, match="outside 1..5"):
        world.lookup("door.spots[6]")
    with pytest.raises(WorldError, match="did you mean 'spots'"):
        world.lookup("door.spot")
    with pytest.raises(WorldError, match="did you mean 'door'"):
        world.lookup("dor.s1")


def test_inline_path_poses_and_frame_references() -> None:
    world = load_world(WORLDS / "arc_welding.yaml")
    seam = world.lookup("plate_joint.seam")
    assert len(seam.points) == 4 and seam.refs == (None,) * 4
    assert world.lookup("plate_joint.calib_path").refs == ("start_pos", "calib_end")
    assert world.relative_pose("laser", "torch").x == pytest.approx(0.03)


def test_model_spatial_and_soft_attributes_are_apart() -> None:
    world = load_world(WORLDS / "materials_handling.yaml")
    pallet = world.object("pallet")
    assert pallet.model.geometry == "box" and pallet.model.size_m == pytest.approx((0.3, 0.4, 0.02))
    assert dict(pallet.spatial) == {"rows": 3, "cols": 4}
    assert dict(world.soft("pallet")) == {"next_row": 1, "next_col": 1}
    assert world.lookup("drop_station.DropPositions[2]") == world.lookup("drop_station.bolt_bin").pose
    grinder = load_world(WORLDS / "deburring.yaml").soft("grinder")
    assert grinder["grinding_time"] == Quantity(0, grinder["grinding_time"].dim)


def test_positions_children_and_the_robot_model(thesis) -> None:
    assert thesis.positions() == ("base_plate.pos1", "base_plate.pos2")
    assert thesis.children("world")[:2] == ("robot", "table")
    assert thesis.children("flange") == ("holder",)
    assert thesis.descendants("fixture") == ("base_plate",)
    assert thesis.ancestors("grinder") == ("holder", "flange", "robot", "world")
    assert thesis.robot_model_file() == str(WORLDS / "irb2400.xml")


def test_two_loads_of_one_file_are_equal_and_an_edit_is_not(thesis) -> None:
    again = load_world(WORLDS / "cell_thesis.yaml")
    assert again == thesis
    assert thesis.with_soft("table", "cycles", 1) != thesis
