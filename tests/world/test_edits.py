"""Changes to a world keep every other byte: teach, add, soft state, affix/unfix, the on-line split, atomic save."""

from __future__ import annotations

import difflib
import math
import os
from pathlib import Path

import numpy as np
import pytest

from orc_rpl.world import Pose, WorldError, load_world, restore_model_attributes, split_model_attributes

WORLDS = Path(__file__).parents[2] / "worlds"
DOWN = (0.0, math.pi, 0.0)


def changed_lines(before: str, after: str) -> list[str]:
    """The lines a change added (+) and removed (-)."""
    diff = difflib.ndiff(before.splitlines(), after.splitlines())
    return [d for d in diff if d[:1] in "+-"]


def comments(text: str) -> list[str]:
    return [line[line.index("#"):] for line in text.splitlines() if "#" in line]


@pytest.fixture
def thesis():
    return load_world(WORLDS / "cell_thesis.yaml")


def test_teaching_a_new_position_in_an_online_frame_adds_one_line(thesis) -> None:
    taught = Pose(0.01, 0.02, 0.06, -math.pi / 2, math.pi, 0, frame="base_plate")   # POS pos1b ... IN base_plate
    after = thesis.with_frame("base_plate", "pos1b", taught)
    assert changed_lines(thesis.dump(), after.dump()) == ["+       pos1b: [10mm, 20mm, 60mm, -90deg, 180deg, 0]"]
    assert np.allclose(after.online_pose("base_plate.pos1b").matrix(), taught.matrix(), atol=1e-12)


def test_touch_up_from_a_world_pose_keeps_the_written_angles(thesis) -> None:
    target = thesis.world_pose("base_plate.pos1").offset(0.005, 0, 0)
    after = thesis.with_frame("base_plate", "pos1", target)
    assert changed_lines(thesis.dump(), after.dump()) == [
        "-       pos1: [50mm, -40mm, 60mm, -90deg, 180deg, 0]",
        "+       pos1: [50mm, -45mm, 60mm, -90deg, 180deg, 0]",
    ]


def test_edits_keep_every_comment(thesis) -> None:
    after = (thesis.with_frame("base_plate", "pos9", Pose(1.0, 0, 0.8, *DOWN))
             .with_soft("base_plate", "parts_done", 3)
             .with_object("clamp", "fixture", Pose(0, 0, 0.05, frame="fixture"), online_frame=True)
             .with_pose("fixture", Pose(0, 0.12, 0, math.pi / 2, 0, 0, frame="table")))
    assert comments(after.dump()) == comments(thesis.dump())
    assert "    pose: [0, 120mm, 0, 90deg, 0, 0]        # turned a quarter on the table" in after.dump()
    assert after.object("clamp").parent == "fixture" and after.object("clamp").online_frame


def test_soft_attributes_read_and_write() -> None:
    world = load_world(WORLDS / "materials_handling.yaml")
    after = world.with_soft("pallet", "next_col", 2).with_soft("pallet", "last_part", "Bolt")
    assert dict(after.soft("pallet")) == {"next_row": 1, "next_col": 2, "last_part": "Bolt"}
    assert "      next_col: 2\n" in after.dump()
    assert "      next_row: 5                          # the next part to take" in after.with_soft("pallet", "next_row", 5).dump()
    assert world.soft("pallet")["next_col"] == 1, "a World never changes; an edit makes a new one"


def test_moving_an_object_moves_its_children(thesis) -> None:
    before = thesis.world_pose("base_plate.pos1")
    after = thesis.with_pose("fixture", thesis.world_pose("fixture").offset(0.01, 0, 0))
    assert np.allclose(after.world_pose("base_plate.pos1").matrix()[:3, 3], [before.x + 0.01, before.y, before.z], atol=1e-12)


def test_affix_keeps_the_world_pose_and_the_part_then_moves_with_the_gripper() -> None:
    flange = Pose(1.0, -0.15, 0.9, *DOWN, frame="robot")
    world = load_world(WORLDS / "assembly.yaml").with_flange(flange)
    bolt_before = world.world_pose("bolt")
    carried = world.affix("bolt", "gripper")
    assert carried.object("bolt").parent == "gripper"
    assert np.allclose(carried.world_pose("bolt").matrix(), bolt_before.matrix(), atol=1e-9)
    moved = carried.with_flange(flange.offset(0.1, 0.2, 0))
    assert np.allclose(moved.world_pose("bolt").matrix()[:3, 3], np.array([0.1, 0.2, 0]) + bolt_before.matrix()[:3, 3], atol=1e-9)
    dropped = moved.unfix("bolt")
    assert dropped.object("bolt").parent == "world"
    assert np.allclose(dropped.with_flange(flange).world_pose("bolt").matrix(), moved.world_pose("bolt").matrix(), atol=1e-9)


def test_affix_carries_children_along(thesis) -> None:
    pos1 = thesis.world_pose("base_plate.pos1")
    affixed = thesis.affix("fixture", "pos3")
    assert np.allclose(affixed.world_pose("base_plate.pos1").matrix(), pos1.matrix(), atol=1e-9)
    shifted = affixed.with_pose("pos3", affixed.world_pose("pos3").offset(0, 0.05, 0))
    assert shifted.world_pose("base_plate.pos1").y == pytest.approx(pos1.y + 0.05, abs=1e-9)


def test_affix_refuses_a_cycle(thesis) -> None:
    with pytest.raises(WorldError, match="hangs below"):
        thesis.affix("fixture", "base_plate")


@pytest.mark.parametrize("path", sorted(WORLDS.glob("*.yaml")), ids=lambda p: p.name)
def test_split_and_restore_of_model_attributes_is_exact(path: Path) -> None:
    world = load_world(path)
    online, store = split_model_attributes(world)
    assert all(o.model is None for o in online.objects)
    assert "geometry:" not in online.dump()
    assert {o.name for o in online.objects if o.model_key} == {o.name for o in world.objects if o.model}
    assert restore_model_attributes(online, store).dump() == world.dump()


def test_a_position_taught_on_line_maps_back_into_the_offline_world(thesis) -> None:
    online, store = split_model_attributes(thesis)
    taught = Pose(0.0, 0.0, 0.07, -math.pi / 2, math.pi, 0, frame="base_plate")
    back = restore_model_attributes(online.with_frame("base_plate", "pos1b", taught), store)
    assert back.dump() == thesis.with_frame("base_plate", "pos1b", taught).dump()


def test_save_is_atomic_and_leaves_the_old_file_when_writing_fails(tmp_path, monkeypatch, thesis) -> None:
    target = tmp_path / "cell.yaml"
    target.write_text("old\n")

    def broken_replace(src: str, dst: str) -> None:
        raise OSError("disk full")

    monkeypatch.setattr(os, "replace", broken_replace)
    with pytest.raises(OSError):
        thesis.save(target)
    assert target.read_text() == "old\n"
    assert os.listdir(tmp_path) == ["cell.yaml"]
    monkeypatch.undo()
    thesis.save(target)
    assert target.read_text() == thesis.dump()
