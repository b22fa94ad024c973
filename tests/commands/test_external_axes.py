"""External axes from the user's side: the demos run in their cell, AXES and moving frames are checked at their line
and column, and positions with axis values travel through the transformation both ways byte for byte."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from orc_rpl.errors import SourceError
from orc_rpl.world import loads_world
from tests.commands.test_hardening import orc
from tests.conftest import ROOT

CELL = ROOT / "worlds" / "positioner_cell.yaml"


def test_the_positioner_demo_ends_on_the_seam_of_the_turned_plate(capsys: pytest.CaptureFixture[str]) -> None:
    code, text = orc(capsys, "run", str(ROOT / "programs/online/demo_positioner.rpl"), "--world", str(CELL), "--seed", "3")
    assert code == 0, text
    off = float(re.search(r"distance from the programmed end on the plate:\s+(\S+) m", text).group(1))  # type: ignore[union-attr]
    assert off < 0.5e-3
    turn = float(re.search(r"turn = (\S+)\) IN plate", text).group(1))  # type: ignore[union-attr]
    assert turn == pytest.approx(1.5708, abs=1e-3)
    assert "final TCP: (950.0, 100.0, 480.0) mm" in text  # the seam's end, turned a quarter about the table's centre


def test_the_track_demo_reaches_the_station_with_the_track_moved(capsys: pytest.CaptureFixture[str]) -> None:
    code, text = orc(capsys, "run", str(ROOT / "programs/online/demo_track.rpl"))  # its '-- world:' line names the cell
    assert code == 0, text
    offs = [float(v) for v in re.findall(r"off (?:the station )?by\s+(\S+) m", text)]
    assert len(offs) == 2 and max(offs) < 0.5e-3
    track = float(re.search(r"track = (\S+), turn", text).group(1))  # type: ignore[union-attr]
    assert track == pytest.approx(0.35, abs=1e-4)


def test_an_offline_program_with_a_positioner_runs_in_its_worlds_cell(capsys: pytest.CaptureFixture[str]) -> None:
    code, text = orc(capsys, "run", str(ROOT / "programs/offline/positioner.orl"))
    assert code == 0, text
    assert "final TCP: (950.0, 100.0, 480.0) mm" in text


BAD = """\
FRAME plate = POSE(0, 0, 0, 0, 0, 0) IN turn
POS a = AXES(POSE(100mm, 50mm, 30mm, 0, 180deg, 0), trun = 90deg)
POS b = AXES(POSE(100mm, 50mm, 30mm, 0, 180deg, 0), track = 90deg)
POS c = AXES(POSE(100mm, 50mm, 30mm, 0, 180deg, 0))
"""


def test_axes_and_moving_frames_are_checked_against_the_cell(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    program = tmp_path / "bad.rpl"
    program.write_text(BAD, encoding="utf-8")
    code, text = orc(capsys, "check", str(program), "--world", str(CELL))
    assert code == 2
    assert f"{program}:2:53: unknown external axis 'trun'; did you mean 'turn'?" in text
    assert f"{program}:3:61: axis 'track' takes a length, got an angle" in text
    assert f"{program}:4:9: AXES needs at least one axis value" in text
    assert "unknown frame" not in text
    code, text = orc(capsys, "check", str(program))  # without the cell, `turn` is no frame
    assert code == 2 and f"{program}:1:41: unknown frame 'turn'" in text


def test_an_axis_value_of_a_world_position_is_checked_at_its_line_and_column() -> None:
    text = CELL.read_text(encoding="utf-8").replace("{turn: 90deg, track: 200mm}", "{turn: 90deg, track: 20deg}")
    with pytest.raises(SourceError) as info:
        loads_world(text, "cell.yaml")
    line = next(i for i, row in enumerate(text.splitlines(), 1) if "track: 20deg" in row)
    assert f"cell.yaml:{line}:" in str(info.value) and "axis 'track' is linear: its value is a length, got '20deg'" in str(info.value)


def test_positions_with_axis_values_convert_both_ways_byte_for_byte(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "worlds").mkdir()
    (tmp_path / "programs" / "offline").mkdir(parents=True)
    world = tmp_path / "worlds" / "cell.yaml"
    shutil.copy(CELL, world)
    offline = tmp_path / "programs" / "offline" / "seam.orl"
    source = (ROOT / "programs/offline/positioner.orl").read_text(encoding="utf-8").replace("positioner_cell", "cell")
    offline.write_text(source, encoding="utf-8")
    online, back = offline.with_name("seam.rpl"), offline.with_name("back.orl")
    assert orc(capsys, "convert", str(offline), "-o", str(online))[0] == 0
    assert "POS seam_end = AXES(POSE(100mm, 50mm, 30mm, 0, 180deg, 0), turn = 90deg, track = 200mm) IN turn" in online.read_text()
    assert orc(capsys, "convert", str(online), "--world", str(world), "-o", str(back))[0] == 0
    assert back.read_text(encoding="utf-8") == source
    assert world.read_bytes() == CELL.read_bytes()
    # a position touched up on-line changes its one line in the world
    online.write_text(online.read_text().replace("turn = 90deg, track = 200mm", "turn = 45deg, track = 150mm"))
    assert orc(capsys, "convert", str(online), "--world", str(world), "-o", str(back))[0] == 0
    changed = [(a, b) for a, b in zip(CELL.read_text().splitlines(), world.read_text().splitlines()) if a != b]
    assert changed == [("      seam_end: [100mm, 50mm, 30mm, 0, 180deg, 0, {turn: 90deg, track: 200mm}]",
                        "      seam_end: [100mm, 50mm, 30mm, 0, 180deg, 0, {turn: 45deg, track: 150mm}]")]
