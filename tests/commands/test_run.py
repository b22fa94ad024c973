"""`orc run`: check first, run on the simulated cell, PRINT to stdout, summary and JSON, exit codes."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from orc_rpl.cli import main

ROOT = Path(__file__).resolve().parents[2]
DEMOS = {
    "demo_pick_and_place": ["placed part 1", "placed part 2", "placed part 3", "done: 3 parts"],
    "demo_pallet": ["pallet full: 12 parts"],
    "demo_io_cycle": ["part found at z = 559 mm; sensor 1", "part found at z = 559 mm; sensor 1", "cycles done: 2"],
    "demo_recover": ["target 1 reached", "target 2 is out of reach; back to safe", "target 3 reached", "reached 2 skipped 1"],
}


def orc(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.sim
@pytest.mark.parametrize("name", DEMOS)
def test_demo_runs_to_completion(name: str, capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    summary = tmp_path / "summary.json"
    code, out, err = orc(capsys, "run", str(ROOT / "programs/online" / f"{name}.rpl"), "--summary-json", str(summary))
    assert code == 0, err
    lines = out.splitlines()
    assert lines[-len(DEMOS[name]):] == DEMOS[name]
    result = json.loads(summary.read_text())
    assert result["status"] == "finished" and result["prints"] == lines and result["error"] is None
    assert "status: finished" in err and "motions:" in err and "final TCP:" in err


@pytest.mark.sim
def test_two_runs_give_identical_summaries_and_recordings(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    program = str(ROOT / "programs/online/demo_recover.rpl")
    for i in (1, 2):
        code, _, err = orc(capsys, "run", program, "--summary-json", str(tmp_path / f"{i}.json"), "--log", str(tmp_path / f"{i}.npz"))
        assert code == 0, err
    assert (tmp_path / "1.json").read_text() == (tmp_path / "2.json").read_text()
    first, second = np.load(tmp_path / "1.npz"), np.load(tmp_path / "2.npz")
    assert first.files == second.files and all(np.array_equal(first[k], second[k], equal_nan=first[k].dtype.kind == "f") for k in first.files)


@pytest.mark.sim
def test_run_time_error_reports_place_and_call_stack(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    program = tmp_path / "bad.rpl"
    program.write_text("POS a = POSE(900mm, 0, 700mm, 0, 180deg, 0)\n"
                       "PROC Go(p)\n"
                       "    MOVE ARM TO OFFS(p, 2000mm, 0, 0)\n"
                       "ENDPROC\n"
                       "MOVE ARM TO a\n"
                       "Go(a)\n"
                       "PRINT \"not reached\"\n")
    summary = tmp_path / "s.json"
    code, out, err = orc(capsys, "run", str(program), "--summary-json", str(summary))
    assert code == 1 and out == ""
    assert f"{program}:3:5: Unreachable: " in err and f"{program}:6:1: in Go" in err and "Traceback" not in err
    error = json.loads(summary.read_text())["error"]
    assert (error["line"], error["column"], error["exception"]) == (3, 5, "Unreachable")
    assert [e["routine"] for e in error["call_stack"]] == ["main", "Go"]


def test_check_errors_exit_2_and_nothing_runs(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    program = tmp_path / "unknown.rpl"
    program.write_text("PRINT \"before\"\nMOVE ARM TO nowhere\n")
    code, out, err = orc(capsys, "run", str(program))
    assert code == 2 and out == "" and f"{program}:2:" in err and "nothing moved" in err


@pytest.mark.parametrize("argv, message", [
    (["run", "no/such/file.rpl"], "cannot read 'no/such/file.rpl'"),
    (["run", "{demo}", "--speed-override", "150%"], "--speed-override"),
    (["run", "{demo}", "--speed-override", "fast"], "--speed-override"),
    (["run", "{demo}", "--robot", "r2d2"], "--robot: unknown robot 'r2d2'"),
    (["run", "{demo}", "--world", "no/such/dir"], "--world"),
    (["run", "{demo}", "--log", "no/such/dir/out.npz"], "--log"),
    (["run", "{demo}", "--sim", "no/such.sim.yaml"], "--sim: no such file 'no/such.sim.yaml'"),
    (["run", "{demo}", "--sim", "/dev/null"], "--sim: '/dev/null' is not a regular file"),
])
def test_usage_errors_are_one_line_and_exit_2(argv: list[str], message: str, capsys: pytest.CaptureFixture[str]) -> None:
    demo = str(ROOT / "programs/online/demo_recover.rpl")
    code, out, err = orc(capsys, *[a.replace("{demo}", demo) for a in argv])
    assert code == 2 and out == ""
    assert message in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err


@pytest.mark.sim
def test_the_same_program_on_the_ideal_and_the_realistic_plant(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    results = {}
    for plant in ("ideal", "realistic"):
        summary = tmp_path / f"{plant}.json"
        code, out, err = orc(capsys, "run", str(ROOT / "programs/online/demo_pick_and_place.rpl"), "--plant", plant,
                             "--seed", "3", "--summary-json", str(summary))
        assert code == 0, err
        results[plant] = (out, json.loads(summary.read_text()))
    (ideal_out, ideal), (real_out, real) = results["ideal"], results["realistic"]
    assert ideal_out == real_out, "the same statements, the same prints"
    position = [[result["final_tcp"][k] for k in ("x_m", "y_m", "z_m")] for result in (ideal, real)]
    assert np.allclose(position[0], position[1], atol=0.5e-3), "the same final position within 0.5 mm"


def test_a_plant_that_does_not_exist_is_a_usage_error(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as stopped:
        main(["run", str(ROOT / "programs/online/demo_pallet.rpl"), "--plant", "perfect"])
    assert stopped.value.code == 2 and "--plant" in capsys.readouterr().err


@pytest.mark.sim
def test_sim_replaces_the_programs_own_equipment(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    # the same deburring program on a casting with a smaller bulge: a variation of the cell, not of the program
    program = ROOT / "programs/online/thesis_2_1_grindmove.rpl"
    own = program.with_suffix(".sim.yaml").read_text(encoding="utf-8")
    assert "height: 1.4mm" in own
    smaller = tmp_path / "smaller.sim.yaml"
    smaller.write_text(own.replace("height: 1.4mm", "height: 0.8mm"), encoding="utf-8")
    heights = []
    for extra in ((), ("--sim", str(smaller))):
        summary = tmp_path / f"summary{len(heights)}.json"
        code, out, err = orc(capsys, "run", str(program), *extra, "--summary-json", str(summary))
        assert code == 0, err
        (bulge,) = json.loads(summary.read_text())["process"]["bulges"]
        assert bulge["within_tolerance"]
        heights.append(bulge["caught_height_m"])
    assert heights[1] < heights[0] - 0.4e-3  # the smaller casting's bulge was the one caught and ground
