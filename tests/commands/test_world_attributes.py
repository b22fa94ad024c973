"""Soft and spatial attributes of world objects (`pallet.next_row`) read by off-line programs and their on-line forms."""

from __future__ import annotations

from pathlib import Path

import pytest

from orc_rpl.cli import main

WORLD = """\
world:
  pallet:
    pose: [900mm, 150mm, 600mm, 0, 0, 0]
    online_frame: true
    frames:
      corner: [0, 0, 100mm, 0, 180deg, 0]
    spatial:
      rows: 3
      pitch: 50mm
    soft:
      next_row: 2
"""

PROGRAM = """\
# world: cell.yaml
moveto pallet.corner
print("row", pallet.next_row, "of", pallet.rows, "pitch", pallet.pitch)
if pallet.next_row < pallet.rows:
    print("next at", pallet.next_row * pallet.pitch)
"""


@pytest.fixture
def cell(tmp_path: Path) -> Path:
    (tmp_path / "cell.yaml").write_text(WORLD)
    (tmp_path / "prog.orl").write_text(PROGRAM)
    return tmp_path


def test_offline_program_reads_them_checked_and_run(cell: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check", str(cell / "prog.orl")]) == 0
    assert main(["run", str(cell / "prog.orl")]) == 0
    assert capsys.readouterr().out.splitlines() == ["row 2 of 3 pitch 0.05 m", "next at 0.1 m"]


def test_the_online_form_reads_them_from_the_world_it_travels_with(cell: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["convert", str(cell / "prog.orl"), "-o", str(cell / "prog.rpl"), "--online-world", str(cell / "online.yaml")]) == 0
    assert "PRINT \"row\", pallet.next_row, \"of\", pallet.rows" in (cell / "prog.rpl").read_text()
    capsys.readouterr()
    assert main(["check", str(cell / "prog.rpl"), "--world", str(cell / "online.yaml")]) == 0
    assert main(["run", str(cell / "prog.rpl"), "--world", str(cell / "online.yaml")]) == 0
    assert capsys.readouterr().out.splitlines() == ["row 2 of 3 pitch 0.05 m", "next at 0.1 m"]
    # Without its world the on-line form cannot know them: a check error, not a failure at run time.
    assert main(["check", str(cell / "prog.rpl")]) == 2
    out = capsys.readouterr().out
    assert f"{cell / 'prog.rpl'}:6:21: 'pallet' has no field 'next_row'; its fields are x, y, z, a, b, c" in out
    assert "read with the program's world (--world FILE)" in out


def test_an_unknown_attribute_is_a_check_error_with_did_you_mean(cell: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (cell / "prog.orl").write_text(PROGRAM + "print(pallet.next_rows)\n")
    assert main(["check", str(cell / "prog.orl")]) == 2
    out = capsys.readouterr().out
    assert f"{cell / 'prog.orl'}:6:14: 'pallet' has no frame, path or attribute 'next_rows'" in out
    assert "did you mean 'next_row'?" in out
    (cell / "online.rpl").write_text("FRAME pallet = POSE(0.9, 0.15, 0.6, 0, 0, 0)\nPRINT pallet.rws\n")
    assert main(["check", str(cell / "online.rpl"), "--world", str(cell / "cell.yaml")]) == 2
    out = capsys.readouterr().out
    assert f"{cell / 'online.rpl'}:2:14: 'pallet' has no attribute 'rws' in the world model; did you mean 'rows'?" in out
