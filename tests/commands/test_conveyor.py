"""A conveyor in the cell through `orc run`: the demo picks every part off the moving belt, motions meet targets on the belt."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from orc_rpl.cli import main

ROOT = Path(__file__).resolve().parents[2]
#: Where the parts are at t = 0 in the cell (worlds/conveyor_cell.yaml: the belt at y = -700 mm, parts 800 mm apart,
#: their tops 50 mm above it) and the belt's speed along y.
PART_TOPS_M = [(0.9, -0.7 - 0.8 * k, 0.45) for k in range(3)]
BELT_SPEED_M_S = 0.1
TOLERANCE_M = 0.002  # the TCP stays within 2 mm of the moving part while it rides with it


def test_the_conveyor_demo_picks_every_part_tracking_it(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    log = tmp_path / "run.npz"
    code = main(["run", str(ROOT / "programs/online/demo_conveyor.rpl"), "--world", str(ROOT / "worlds/conveyor_cell.yaml"),
                 "--log", str(log)])
    out = capsys.readouterr().out
    assert code == 0, out
    assert "pick motions done on the moving belt: 3" in out
    data = np.load(log)
    names = [str(name) for name in data["__names__"]]  # the signals are stored as s0, s1, ... in this order
    t, tcp = data["time_s"], data[f"s{names.index('tool_tcp')}"]
    # riding: the TCP at the parts' top height (measured in the cell); three separate rides, one per part
    riding = np.abs(tcp[:, 2] - 0.45) < 1e-3
    starts = np.flatnonzero(np.diff(riding.astype(int)) == 1)
    assert len(starts) == 3
    assert riding.sum() * float(t[1] - t[0]) > 3 * 0.5  # each ride lasts over half a second
    parts = [np.stack([np.full_like(t, x), y + BELT_SPEED_M_S * t, np.full_like(t, z)], axis=1) for x, y, z in PART_TOPS_M]
    nearest = np.min([np.linalg.norm(tcp - p, axis=1) for p in parts], axis=0)
    assert nearest[riding].max() < TOLERANCE_M


RIDE = """\
TOOL gripper = POSE(0, 0, 150mm, 0, 0, 0)
MOVE gripper TO POSE(900mm, -300mm, 550mm, 0, 180deg, 0)
FRAME belt
    start = HERE
ENDFRAME
FUNC ride(t)
    RETURN start
ENDFUNC
before = HERE
FRAME belt
    LMOVE gripper TO ride WITH TIME = 1s
ENDFRAME
PRINT "carried ", HERE.y - before.y
"""


def test_a_function_of_time_relative_to_a_belt_rides_with_it(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    program, log = tmp_path / "ride.rpl", tmp_path / "ride.npz"
    program.write_text(RIDE)
    assert main(["run", str(program), "--world", str(ROOT / "worlds/conveyor_cell.yaml"), "--log", str(log)]) == 0
    carried_m = float(capsys.readouterr().out.split("carried ")[1].split()[0])
    assert carried_m == pytest.approx(BELT_SPEED_M_S * 1.0, abs=1e-3)  # where the belt took the pose in the motion's TIME
    data = np.load(log)
    names = [str(name) for name in data["__names__"]]
    t, y = data["time_s"], data[f"s{names.index('tool_tcp')}"][:, 1]
    riding = np.flatnonzero(np.abs(np.gradient(y, t) - BELT_SPEED_M_S) < 0.1 * BELT_SPEED_M_S)
    assert t[riding[-1]] - t[riding[0]] > 0.9
    assert np.ptp(y[riding] - BELT_SPEED_M_S * t[riding]) < 1e-3  # still relative to the belt while riding


MEET = """\
TOOL gripper = POSE(0, 0, 150mm, 0, 0, 0)
FRAME part1 = POSE(0, 0, 0, 0, 0, 0) IN belt
POS top = POSE(0, 0, 50mm, 0, 180deg, 0) IN part1
FRAME part1
    MOVE gripper TO OFFS(top, 0, 400mm, 100mm)
    LMOVE gripper TO OFFS(top, 0, 300mm, 100mm)
ENDFRAME
"""


@pytest.mark.parametrize("plant", ["realistic", "elastic-gears"])
def test_a_motion_to_a_target_on_the_belt_ends_where_the_belt_has_carried_it(tmp_path: Path, plant: str) -> None:
    """On elastic gears too, whose averaged starts make a move's duration change nearly as fast as the belt carries
    its target away (the duration's prediction repeated alone left the LMOVE 2.3 mm behind)."""
    program, log = tmp_path / "meet.rpl", tmp_path / "meet.npz"
    program.write_text(MEET)
    assert main(["run", str(program), "--world", str(ROOT / "worlds/conveyor_cell.yaml"), "--log", str(log),
                 "--plant", plant]) == 0
    data = np.load(log)
    names = [str(name) for name in data["__names__"]]
    t, tcp, s = data["time_s"], data[f"s{names.index('tool_tcp')}"], data[f"s{names.index('s')}"]
    ends = np.flatnonzero((s[1:] >= 1.0) & (s[:-1] < 1.0)) + 1  # when each motion's path reaches its end
    assert len(ends) == 2
    x, y, z = PART_TOPS_M[0]
    for i, ahead_m in zip(ends, (0.4, 0.3)):
        target = np.array([x, y + ahead_m + BELT_SPEED_M_S * t[i], z + 0.1])  # where the belt has carried it by then
        assert np.linalg.norm(tcp[i] - target) < 1e-3
