"""The cell made from a world model: its objects as solids, contacts on, a collision stops the robot at its statement."""

from __future__ import annotations

import json
import textwrap
from pathlib import Path

import numpy as np
import pytest

from orc_rpl.cli import main
from orc_rpl.errors import UsageError
from orc_rpl.plant.sim import SimCell
from orc_rpl.plant.world_scene import cell_from_world
from orc_rpl.world import load_world, loads_world

ROOT = Path(__file__).resolve().parents[2]

WORLD = """\
robot:
  model: irb2400
  pose: [0, 0, 0, 0, 0, 0]

world:
  block:
    pose: [900mm, 0, 300mm, 0, 0, 0]
    model:
      geometry: box
      size: [300mm, 300mm, 300mm]
  part:
    pose: [900mm, 400mm, 300mm, 0, 0, 0]
    work: true
    model:
      geometry: box
      size: [200mm, 200mm, 300mm]
"""

PROGRAM = """\
POS above = POSE(900mm, 0, 700mm, 0, 180deg, 0)
POS inside = POSE(900mm, 0, 300mm, 0, 180deg, 0)
POS on_part = POSE(900mm, 400mm, 440mm, 0, 180deg, 0)
MOVE ARM TO above
LMOVE ARM TO on_part WITH SPEED = 0.2mps
LMOVE ARM TO above
PRINT "before"
LMOVE ARM TO inside WITH SPEED = 0.2mps
PRINT "not reached"
"""


def test_shaped_objects_become_solids_in_the_world_or_on_the_flange() -> None:
    cell = cell_from_world(load_world(ROOT / "worlds" / "deburring.yaml"))
    solids = {s.name: s for s in cell.solids}
    assert cell.contacts and cell.robot == "irb2400"
    assert set(solids) == {"table", "casting", "holder", "grinder"}
    assert solids["casting"].work and not solids["table"].work
    assert solids["grinder"].on_flange and not solids["table"].on_flange
    # the table top's centre is 300 mm below its pose (its offset), the casting sits on it
    assert np.allclose(solids["table"].position_m, (1.0, 0.0, 0.3))
    assert np.allclose(solids["casting"].position_m, (1.0, -0.1, 0.64))
    sim = SimCell(cell=cell)
    assert sim.collision is None, "nothing touches at home"


@pytest.mark.sim
def test_a_collision_stops_the_robot_and_fails_its_statement(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "cell.yaml").write_text(WORLD)
    (tmp_path / "prog.rpl").write_text(PROGRAM)
    summary = tmp_path / "summary.json"
    code = main(["run", str(tmp_path / "prog.rpl"), "--world", str(tmp_path / "cell.yaml"), "--summary-json", str(summary)])
    out, err = capsys.readouterr()
    assert code == 1
    assert out.splitlines() == ["before"], "touching the part (work) is no collision; the block is"
    assert "prog.rpl:8:1: Collision: collision between link5 and block" in err
    tcp = json.loads(summary.read_text())["final_tcp"]
    assert tcp["z_m"] > 0.45, "stopped at once, above the block's top, not driven on towards the target"


def test_a_robot_turned_on_its_base_is_refused() -> None:
    world = loads_world(textwrap.dedent("""\
        robot:
          model: irb2400
          pose: [0, 0, 0, 90deg, 0, 0]
        world:
          block:
            pose: [900mm, 0, 300mm, 0, 0, 0]
        """))
    with pytest.raises(UsageError, match="upright"):
        cell_from_world(world)


#: Into the block, the Collision caught, and back off.
BACK_OFF = textwrap.dedent("""\
        POS above = POSE(900mm, 0, 700mm, 0, 180deg, 0)
        POS inside = POSE(900mm, 0, 300mm, 0, 180deg, 0)
        MOVE ARM TO above
        TRY
            LMOVE ARM TO inside WITH SPEED = 0.2mps
        ON Collision :
            PRINT "collision caught"
            LMOVE ARM TO above WITH SPEED = 0.1mps
        ENDTRY
        PRINT "done"
        """)


@pytest.mark.sim
def test_a_caught_collision_lets_the_robot_back_off(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "cell.yaml").write_text(WORLD)
    (tmp_path / "prog.rpl").write_text(BACK_OFF)
    code = main(["run", str(tmp_path / "prog.rpl"), "--world", str(tmp_path / "cell.yaml")])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert out.splitlines() == ["collision caught", "done"]


@pytest.mark.sim
def test_a_caught_collision_lets_the_robot_back_off_on_elastic_gears(tmp_path: Path,
                                                                     capsys: pytest.CaptureFixture[str]) -> None:
    # stopped on the block, the links swing back onto it once through their gears (apart 36 ms, touching again 77 ms
    # after the collision): the same collision's rebound, not a new one that stops the back-off
    (tmp_path / "cell.yaml").write_text(WORLD)
    (tmp_path / "prog.rpl").write_text(BACK_OFF)
    code = main(["run", str(tmp_path / "prog.rpl"), "--world", str(tmp_path / "cell.yaml"), "--plant", "elastic-gears"])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert out.splitlines() == ["collision caught", "done"]

