"""Every world in worlds/ reads back byte for byte, and every position in it is one the robot can reach tool-down."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from orc_rpl.world import load_world, loads_world

WORLDS = sorted((Path(__file__).parents[2] / "worlds").glob("*.yaml"))
THESIS_APPLICATIONS = {"cell_thesis", "deburring", "spot_welding", "arc_welding", "assembly", "materials_handling"}


def test_there_is_a_world_per_thesis_application() -> None:
    assert THESIS_APPLICATIONS <= {p.stem for p in WORLDS}


@pytest.mark.parametrize("path", WORLDS, ids=lambda p: p.name)
def test_world_file_round_trips_byte_for_byte(path: Path, tmp_path: Path) -> None:
    world = load_world(path)
    assert world.dump().encode() == path.read_bytes()
    world.save(tmp_path / path.name)
    assert (tmp_path / path.name).read_bytes() == path.read_bytes()


@pytest.mark.parametrize("path", WORLDS, ids=lambda p: p.name)
def test_every_position_is_in_the_table_workspace_with_the_tool_down(path: Path) -> None:
    world = load_world(path)
    names = [f"{o.name}.{f.name}" for o in world.objects for f in o.frames]
    names += [f"{o.name}.{p.name}[{i}]" for o in world.objects for p in o.paths for i in range(1, len(p.points) + 1)]
    if path.stem == "cell_thesis":
        names += ["pos0", "pos3"]
    assert names
    for name in names:
        pose = world.world_pose(name)
        assert 0.7 <= pose.x <= 1.2 and -0.4 <= pose.y <= 0.4 and 0.4 <= pose.z <= 1.1, f"{name} outside the workspace: {pose}"
        down = np.diag([-1.0, 1.0, -1.0])  # Ry(180deg): a = 0, b = 180deg, c = 0
        assert np.allclose(pose.matrix()[:3, :3], down, atol=1e-9), f"{name}: the tool must point down"


def test_crlf_file_round_trips_and_edits_keep_crlf() -> None:
    text = "# cell\r\nworld:\r\n  plate:\r\n    pose: [1m, 0, 0, 0, 0, 0]   # here\r\n"
    world = loads_world(text)
    assert world.dump() == text
    edited = world.with_soft("plate", "count", 2)
    assert edited.dump() == text + "    soft:\r\n      count: 2\r\n"


def test_file_without_final_newline_round_trips() -> None:
    text = "world:\n  plate:\n    pose: [1m, 0, 0, 0, 0, 0]"
    assert loads_world(text).dump() == text
    assert loads_world(text).with_frame("plate", "p", loads_world(text).world_pose("plate")).dump().endswith(
        "    pose: [1m, 0, 0, 0, 0, 0]\n    frames:\n      p: [0, 0, 0, 0, 0, 0]\n")


def test_empty_world_has_no_objects() -> None:
    assert loads_world("# nothing yet\n").objects == ()
