"""`orc convert`, `orc diff`, and `orc check`/`orc fmt` on off-line programs, as a user runs them."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from orc_rpl.cli import main

ROOT = Path(__file__).resolve().parent.parent.parent
THESIS = ROOT / "programs" / "offline" / "thesis_7_3.orl"
CELL = ROOT / "worlds" / "cell_thesis.yaml"


@pytest.fixture
def cell(tmp_path: Path) -> Path:
    shutil.copy(CELL, tmp_path / "cell.yaml")
    (tmp_path / "prog.orl").write_text("moveto pos0\nmoveto base_plate.pos1\nmoveto base_plate.pos2\nmoveto pos3\n")
    return tmp_path


def test_convert_both_ways_gives_back_program_and_world(cell: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (cell / "prog.orl").write_text("# world: cell.yaml\n" + (cell / "prog.orl").read_text())
    assert main(["convert", str(cell / "prog.orl"), "--to", "online", "--world", str(cell / "cell.yaml"),
                 "-o", str(cell / "prog.rpl"), "--online-world", str(cell / "online.yaml")]) == 0
    online = (cell / "prog.rpl").read_text()
    assert "FRAME base_plate\n    MOVE ARM TO pos1\n    MOVE ARM TO pos2\nENDFRAME\n" in online
    assert "model_key: base_plate" in (cell / "online.yaml").read_text()
    assert main(["convert", str(cell / "prog.rpl"), "--to", "offline", "--world", str(cell / "cell.yaml"),
                 "-o", str(cell / "back.orl")]) == 0
    assert (cell / "back.orl").read_text() == (cell / "prog.orl").read_text()
    assert (cell / "cell.yaml").read_text() == CELL.read_text()
    assert "wrote" in capsys.readouterr().err


def test_convert_offline_writes_taught_positions_into_the_world(cell: Path) -> None:
    main(["convert", str(cell / "prog.orl"), "--world", str(cell / "cell.yaml"), "-o", str(cell / "prog.rpl")])
    edited = (cell / "prog.rpl").read_text().replace("    MOVE ARM TO pos2\n", "    MOVE ARM TO pos2\n    MOVE ARM TO pos2b\n")
    edited = edited.replace("POS pos3", "POS pos2b = POSE(-50mm, 60mm, 60mm, -90deg, 180deg, 0) IN base_plate\nPOS pos3")
    (cell / "prog.rpl").write_text(edited)
    assert main(["convert", str(cell / "prog.rpl"), "--world", str(cell / "cell.yaml"), "-o", str(cell / "prog.orl")]) == 0
    assert "moveto base_plate.pos2\nmoveto base_plate.pos2b\n" in (cell / "prog.orl").read_text()
    assert "      pos2b: [-50mm, 60mm, 60mm, -90deg, 180deg, 0]\n" in (cell / "cell.yaml").read_text()


def test_convert_an_online_program_makes_its_world(tmp_path: Path) -> None:
    source = ROOT / "programs" / "online" / "thesis_7_3_online_frame.rpl"
    world, orl, rpl = tmp_path / "made.yaml", tmp_path / "p.orl", tmp_path / "p.rpl"
    assert main(["convert", str(source), "--world", str(world), "-o", str(orl)]) == 0
    assert "online_frame: true" in world.read_text()
    assert main(["convert", str(orl), "--world", str(world), "-o", str(rpl)]) == 0
    assert rpl.read_text() == source.read_text()


def test_convert_error_writes_nothing_and_keeps_the_old_output(cell: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (cell / "bad.orl").write_text("moveto pos0\nmoveto base_plate.pos9\n")
    (cell / "out.rpl").write_text("old\n")
    assert main(["convert", str(cell / "bad.orl"), "--world", str(cell / "cell.yaml"), "-o", str(cell / "out.rpl")]) == 2
    err = capsys.readouterr().err
    assert f"{cell / 'bad.orl'}:2:19: 'base_plate' has no frame, path or attribute 'pos9'" in err
    assert "did you mean 'pos" in err and "nothing was written" in err
    assert (cell / "out.rpl").read_text() == "old\n"
    assert sorted(p.name for p in cell.iterdir()) == ["bad.orl", "cell.yaml", "out.rpl", "prog.orl"]


def test_convert_bad_world_is_reported_at_its_line(cell: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (cell / "cell.yaml").write_text("world:\n  plate:\n    parent: tabel\n")
    assert main(["convert", str(cell / "prog.orl"), "--world", str(cell / "cell.yaml"), "-o", str(cell / "p.rpl")]) == 2
    assert f"{cell / 'cell.yaml'}:3:13: unknown parent 'tabel' of 'plate'" in capsys.readouterr().err
    assert not (cell / "p.rpl").exists()


@pytest.mark.parametrize("args, message", [
    (["--to", "offline"], "is already an off-line program"),
    (["-o", "x.orl"], "an online program is written to a '.rpl' file"),
    ([], "give its world model"),
])
def test_convert_usage_errors_name_the_argument(cell: Path, capsys: pytest.CaptureFixture[str], args: list[str],
                                               message: str) -> None:
    assert main(["convert", str(cell / "prog.orl"), *args]) == 2
    assert message in capsys.readouterr().err


def test_diff_is_empty_between_a_program_and_its_conversion(cell: Path, capsys: pytest.CaptureFixture[str]) -> None:
    main(["convert", str(cell / "prog.orl"), "--world", str(cell / "cell.yaml"), "-o", str(cell / "prog.rpl")])
    capsys.readouterr()
    assert main(["diff", str(cell / "prog.orl"), str(cell / "prog.rpl"), "--world", str(cell / "cell.yaml")]) == 0
    assert capsys.readouterr().out == ""


def test_diff_shows_moved_positions_and_new_statements(cell: Path, capsys: pytest.CaptureFixture[str]) -> None:
    main(["convert", str(cell / "prog.orl"), "--world", str(cell / "cell.yaml"), "-o", str(cell / "prog.rpl")])
    edited = (cell / "prog.rpl").read_text().replace("POSE(-50mm, 40mm", "POSE(-51mm, 40mm") + "WAIT 1s  -- new\n"
    (cell / "edited.rpl").write_text(edited.replace("-- new", "-- comments do not count"))
    capsys.readouterr()
    assert main(["diff", str(cell / "prog.orl"), str(cell / "edited.rpl"), "--world", str(cell / "cell.yaml")]) == 1
    out = capsys.readouterr().out
    assert "~ POS pos2 changed" in out and "+WAIT 1s" in out and "pos1" not in out.replace("pos1 ", "")


def test_check_offline_program_reports_unknown_world_path_with_did_you_mean(cell: Path,
                                                                           capsys: pytest.CaptureFixture[str]) -> None:
    (cell / "bad.orl").write_text("moveto pos0\nmoveto base_plate.pos3\n")
    assert main(["check", str(cell / "bad.orl"), "--world", str(cell / "cell.yaml")]) == 2
    out = capsys.readouterr().out
    assert f"{cell / 'bad.orl'}:2:19: 'base_plate' has no frame, path or attribute 'pos3'" in out
    assert "      |                   ^^^^" in out and "did you mean 'pos" in out


def test_check_and_fmt_accept_the_offline_programs() -> None:
    programs = sorted(str(p) for p in (ROOT / "programs" / "offline").glob("*.orl"))
    assert main(["check", *programs]) == 0
    assert main(["fmt", "--check", *programs]) == 0


def test_fmt_writes_canonical_offline_text(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    program = tmp_path / "p.orl"
    program.write_text("moveto   pos0  speed=0.5*Vmax\nif x :\n  wait 1s\n")
    assert main(["fmt", "--write", str(program), "--world", str(CELL)]) == 0
    assert program.read_text() == "moveto pos0 speed=0.5 * Vmax\nif x:\n    wait 1s\n"
    program.write_text("moveto base_plate.posX\n")
    assert main(["fmt", "--write", str(program), "--world", str(CELL)]) == 2
    assert program.read_text() == "moveto base_plate.posX\n"
    assert "p.orl:1:19:" in capsys.readouterr().out


def test_convert_refuses_an_online_name_that_is_an_offline_keyword(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "p.rpl").write_text("VAR step = 1\nPRINT step\n")
    assert main(["convert", str(tmp_path / "p.rpl"), "--world", str(tmp_path / "w.yaml"), "-o", str(tmp_path / "p.orl")]) == 2
    assert "the name 'step' (line 1) is an off-line keyword" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.rpl"]


def test_run_offline_program_moves_like_its_online_form(cell: Path) -> None:
    import json

    main(["convert", str(cell / "prog.orl"), "--world", str(cell / "cell.yaml"), "-o", str(cell / "prog.rpl")])
    assert main(["run", str(cell / "prog.orl"), "--world", str(cell / "cell.yaml"), "--summary-json", str(cell / "off.json")]) == 0
    assert main(["run", str(cell / "prog.rpl"), "--summary-json", str(cell / "on.json")]) == 0
    offline, online = (json.loads((cell / name).read_text()) for name in ("off.json", "on.json"))
    assert offline == online and offline["motions"] == 4 and offline["status"] == "finished"


def test_run_offline_program_finds_its_world_by_its_world_line(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", str(THESIS)]) == 0
    assert "motions: 4" in capsys.readouterr().err


def test_convert_refuses_a_program_with_check_errors(cell: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (cell / "bad.rpl").write_text("POS p = POSE(0.8, 0, 0.6, 0, 180deg, 0)\nMOVE ARM TO p\nWAIT 3N\n")
    (cell / "bad.orl").write_text("moveto pos0\nwait 3N\n")
    assert main(["convert", str(cell / "bad.rpl"), "--world", str(cell / "new.yaml"), "-o", str(cell / "bad_out.orl")]) == 2
    err = capsys.readouterr().err
    assert f"{cell / 'bad.rpl'}:3:6: WAIT expects a time, got a force" in err and "nothing was written" in err
    assert main(["convert", str(cell / "bad.orl"), "--world", str(cell / "cell.yaml"), "-o", str(cell / "bad_out.rpl")]) == 2
    assert f"{cell / 'bad.orl'}:2:6: WAIT expects a time, got a force" in capsys.readouterr().err
    assert not (cell / "new.yaml").exists() and not (cell / "bad_out.orl").exists() and not (cell / "bad_out.rpl").exists()


def test_convert_names_the_world_it_used(cell: Path) -> None:
    (cell / "sub").mkdir()
    (cell / "prog.orl").write_text("# world: stale/old.yaml\n# a comment\nmoveto pos0\n")
    assert main(["convert", str(cell / "prog.orl"), "--world", str(cell / "cell.yaml"), "-o", str(cell / "prog.rpl")]) == 0
    assert "world:" not in (cell / "prog.rpl").read_text()
    assert main(["convert", str(cell / "prog.rpl"), "--world", str(cell / "cell.yaml"), "-o", str(cell / "sub" / "p.orl")]) == 0
    assert (cell / "sub" / "p.orl").read_text() == "# world: ../cell.yaml\n# a comment\nmoveto pos0\n"


def test_convert_moves_declarations_after_an_install_into_the_new_world(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    world, orl, rpl = tmp_path / "pallet.yaml", tmp_path / "pallet.orl", tmp_path / "pallet.rpl"
    source = ROOT / "programs" / "online" / "demo_pallet.rpl"
    assert main(["convert", str(source), "--world", str(world), "-o", str(orl)]) == 0
    made = world.read_text()
    for entry in ("  gripper:\n", "  pallet:\n", "      corner1: [0, 0, 30mm, 0, 180deg, 0]\n", "  feeder:\n"):
        assert entry in made
    offline = orl.read_text()
    assert offline.startswith("# world: pallet.yaml\n")
    assert "pos corner1" not in offline and "return OFFS(pallet.corner1, " in offline
    assert main(["convert", str(orl), "-o", str(rpl)]) == 0
    assert main(["run", str(rpl)]) == 0
    assert capsys.readouterr().out.splitlines()[-1] == "pallet full: 12 parts"
