"""`ALONG f` with a FUNC f of s or of t: the TCP follows the function as a path, through orc check, orc run and orc convert."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from orc_rpl.cli import main

ROOT = Path(__file__).resolve().parent.parent.parent
CELL = ROOT / "worlds" / "cell_thesis.yaml"

WAVE = """\
POS start = POSE(0.8, 0, 0.6, 0, 180deg, 0)
FUNC wave(s)
    RETURN OFFS(start, 0.1 * s, 0.02 * SIN(s * 6.2832), 0)
ENDFUNC
FUNC conveyor(t)
    RETURN OFFS(start, 0.1mps * t, 0, 0)
ENDFUNC
LMOVE ARM TO start
"""


def _run(program: Path, tmp_path: Path, extra: list[str] | None = None) -> dict:
    summary = tmp_path / "summary.json"
    assert main(["run", str(program), "--plant", "ideal", "--summary-json", str(summary), *(extra or [])]) == 0
    return json.loads(summary.read_text())


@pytest.mark.parametrize("motion, end", [("LMOVE ARM {} wave WITH SPEED = 0.1mps", "900 0"),
                                         ("LMOVE ARM {} conveyor WITH TIME = 2s", "1000 0")], ids=["of s", "of t"])
def test_along_a_func_follows_it_as_a_path(motion: str, end: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    summaries = []
    for word in ("ALONG", "TO"):
        program = tmp_path / f"{word}.rpl"
        program.write_text(WAVE + motion.format(word) + "\nPRINT ROUND(HERE.x / 1mm, 1), ROUND(HERE.y / 1mm, 1)\n")
        assert main(["check", str(program)]) == 0, capsys.readouterr().out
        summaries.append(_run(program, tmp_path))
    assert capsys.readouterr().out.splitlines().count(end) == 2
    along, to = summaries
    assert along["cycle_time_s"] == to["cycle_time_s"] and along["final_tcp"] == to["final_tcp"]


#: Programs ALONG a FUNC that `orc check` refuses: the program's tail after WAVE, and the error at its line and column.
ALONG_ERRORS = [
    ("LMOVE ARM ALONG conveyor\n",
     "9:17: FUNC conveyor(t) is a function of time: the motion needs its duration"),
    ("FRAME table = POSE(0.8, 0, 0.5, 0, 0, 0)\nFRAME table\n    LMOVE ARM ALONG wave\nENDFRAME\n",
     "11:21: FUNC wave gives poses relative to world (line 3), but this motion is inside FRAME table"),
    ("FUNC speed(s)\n    RETURN 20mm\nENDFUNC\nLMOVE ARM ALONG speed\n",
     "12:17: FUNC speed given as a path must give poses; line 10 gives"),
]


@pytest.mark.parametrize("tail, error", ALONG_ERRORS, ids=["duration", "frame", "no poses"])
def test_along_a_func_that_cannot_be_a_path_is_a_check_error(tail: str, error: str, tmp_path: Path,
                                                              capsys: pytest.CaptureFixture[str]) -> None:
    program = tmp_path / "prog.rpl"
    program.write_text(WAVE + tail)
    assert main(["check", str(program)]) == 2
    assert f"{program}:{error}" in capsys.readouterr().out


@pytest.mark.parametrize("function, motion, gives", [
    ("FUNC lift(s)\n    RETURN 2 * s\nENDFUNC\n", "LMOVE ARM TO lift", "a number"),
    ("FUNC lift(t)\n    RETURN 0.1mps * t\nENDFUNC\n", "LMOVE ARM ALONG lift WITH TIME = 1s", "a length"),
])
def test_a_func_whose_return_depends_on_its_parameter_alone_is_typed_at_check(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], function: str, motion: str, gives: str) -> None:
    program = tmp_path / "prog.rpl"
    program.write_text(WAVE + function + motion + "\n")
    assert main(["check", str(program)]) == 2  # the run would fail at the motion; the check says it first
    assert f"{program}:12:" in (out := capsys.readouterr().out) and f"line 10 gives {gives}" in out


OFFLINE = """\
# world: cell.yaml
func wave(s):
    return OFFS(base_plate.pos1, 0.1 * s, 0.02 * SIN(s * 6.2832), 0)
moveto base_plate.pos1
frame base_plate:
    lmove ARM along wave speed=0.1mps
moveto base_plate.pos2
"""


@pytest.mark.parametrize("word", ["along", "to"])
def test_an_offline_func_path_checks_runs_and_converts_both_ways(word: str, tmp_path: Path,
                                                                 capsys: pytest.CaptureFixture[str]) -> None:
    shutil.copy(CELL, tmp_path / "cell.yaml")
    source = tmp_path / "prog.orl"
    source.write_text(OFFLINE.replace("along wave", f"{word} wave"))
    assert main(["check", str(source)]) == 0, capsys.readouterr().out
    offline_run = _run(source, tmp_path)
    online = tmp_path / "prog.rpl"
    assert main(["convert", str(source), "-o", str(online), "--online-world", str(tmp_path / "online.yaml")]) == 0
    text = online.read_text()
    # the FUNC's poses are relative to base_plate: its motion stays inside the block, the others get their own
    assert f"FRAME base_plate\n    LMOVE ARM {word.upper()} wave WITH SPEED = 0.1mps\nENDFRAME\n" in text, text
    assert _run(online, tmp_path, ["--world", str(tmp_path / "online.yaml")])["final_tcp"] == offline_run["final_tcp"]
    back = tmp_path / "back.orl"
    assert main(["convert", str(online), "--world", str(tmp_path / "cell.yaml"), "-o", str(back)]) == 0
    assert back.read_text() == source.read_text()
    assert main(["check", str(back)]) == 0


def test_a_world_func_between_positions_of_an_online_frame_is_not_pulled_into_its_block(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    shutil.copy(CELL, tmp_path / "cell.yaml")
    source = tmp_path / "prog.orl"
    source.write_text("# world: cell.yaml\nfunc lift(s):\n    return POSE(1.0, 0.1, 0.75 + 0.05 * s, 0, 180deg, 0)\n"
                      "moveto base_plate.pos1\nlmove ARM along lift\n"
                      "moveto base_plate.pos2\n")
    assert main(["check", str(source)]) == 0, capsys.readouterr().out
    online = tmp_path / "prog.rpl"
    assert main(["convert", str(source), "-o", str(online), "--online-world", str(tmp_path / "online.yaml")]) == 0
    text = online.read_text()
    assert "ENDFRAME\nLMOVE ARM ALONG lift\nFRAME base_plate\n" in text, text  # between two blocks, relative to world
    assert main(["check", str(online), "--world", str(tmp_path / "online.yaml")]) == 0, capsys.readouterr().out
    back = tmp_path / "back.orl"
    assert main(["convert", str(online), "--world", str(tmp_path / "cell.yaml"), "-o", str(back)]) == 0
    assert back.read_text() == source.read_text()


def test_a_func_path_inside_a_loop_is_not_pulled_into_the_block_of_its_neighbours(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    shutil.copy(CELL, tmp_path / "cell.yaml")
    source = tmp_path / "prog.orl"
    source.write_text("# world: cell.yaml\nfunc lift(s):\n    return POSE(1.0, 0.1, 0.75 + 0.05 * s, 0, 180deg, 0)\n"
                      "for i in 1..2:\n    moveto base_plate.pos1\n    lmove ARM along lift\n    moveto base_plate.pos2\n")
    assert main(["check", str(source)]) == 0, capsys.readouterr().out
    online = tmp_path / "prog.rpl"
    assert main(["convert", str(source), "-o", str(online), "--online-world", str(tmp_path / "online.yaml")]) == 0
    text = online.read_text()
    assert "    ENDFRAME\n    LMOVE ARM ALONG lift\n    FRAME base_plate\n" in text, text
    assert main(["check", str(online), "--world", str(tmp_path / "online.yaml")]) == 0, capsys.readouterr().out
