"""`orc verify`: every program run as `orc run` runs it, on local workers and on a separate Dask cluster; judged."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from tests.plant.test_world_scene import WORLD
from tests.verify.conftest import ROOT, SUBSET, alone, dask_cluster, orc, same_as_alone

#: 80 mm above the block of WORLD (line 3) and back up.
NEAR_THE_BLOCK = ("MOVE ARM TO POSE(900mm, 0, 800mm, 0, 180deg, 0)\nLMOVE ARM TO POSE(900mm, 0, 700mm, 0, 180deg, 0)\n"
                  "LMOVE ARM TO POSE(900mm, 0, 560mm, 0, 180deg, 0) WITH SPEED = 0.2mps\n"
                  "LMOVE ARM TO POSE(900mm, 0, 800mm, 0, 180deg, 0)\n")


@pytest.mark.sim
def test_verify_matches_each_program_run_alone_and_judges_it(extra_programs: dict[str, Path], tmp_path: Path) -> None:
    reference = {shown: alone(ROOT / shown) for shown in SUBSET}
    reference["unreachable"] = alone(extra_programs["unreachable.rpl"])
    slower = SUBSET[1]  # its baseline says it used to be 10 % faster
    baseline = {"version": 1, "runs": {f"{shown} [irb2400]": {"cycle_time_s": summary["cycle_time_s"]
                                                              * (1 / 1.1 if shown == slower else 1.0)}
                                       for shown, summary in reference.items() if shown in SUBSET}}
    (tmp_path / "baseline.json").write_text(json.dumps(baseline), encoding="utf-8")
    result = orc("verify", *SUBSET, *(str(p) for p in extra_programs.values()), "--robot", "irb2400",
                 "--workers", "2", "--min-clearance", "20", "--baseline", str(tmp_path / "baseline.json"), "--json", str(tmp_path / "r.json"),
                 "--junit", str(tmp_path / "j.xml"), "--save-baseline", str(tmp_path / "new.json"))
    assert result.returncode == 1, result.stderr
    rows = {Path(row["program"]).name: row for row in json.loads((tmp_path / "r.json").read_text())["runs"]}
    for shown in SUBSET:
        same_as_alone(rows[Path(shown).name], reference[shown])
    same_as_alone(rows["unreachable.rpl"], reference["unreachable"])
    assert rows["unreachable.rpl"]["verdict"] == "ok" and rows["unreachable.rpl"]["exception"] == "Unreachable"
    assert rows["not_as_expected.rpl"]["verdict"] == "FAIL"
    assert rows["not_as_expected.rpl"]["reasons"] == ["expected Unreachable, got finished"]
    assert rows["ur5e_only.rpl"]["verdict"] == "skipped"
    collided = rows["collides.rpl"]
    assert collided["status"] == "finished" and collided["verdict"] == "FAIL" and collided["clearance_mm"] < 0
    assert collided["reasons"][0].startswith("collision: link") and "to table_top at " in collided["reasons"][0]
    assert collided["clearance_at"] == f"{extra_programs['collides.rpl']}:4", "the LMOVE into the table"
    assert all(rows[Path(shown).name]["clearance_mm"] > 20 for shown in SUBSET)
    assert rows[Path(slower).name]["verdict"] == "FAIL"
    assert rows[Path(slower).name]["reasons"][0].startswith("10.0 % slower than the baseline")
    assert rows[Path(SUBSET[0]).name]["change_pct"] == 0.0 and rows[Path(SUBSET[0]).name]["verdict"] == "ok"
    suite = ET.parse(tmp_path / "j.xml").getroot()
    assert (suite.get("tests"), suite.get("failures"), suite.get("skipped")) == ("7", "3", "1")
    saved = json.loads((tmp_path / "new.json").read_text())["runs"]
    assert saved[f"{SUBSET[1]} [irb2400]"]["cycle_time_s"] == reference[SUBSET[1]]["cycle_time_s"]
    for shown in SUBSET:
        assert shown in result.stdout  # the table lists every program
    assert "7 runs: 3 ok, 3 failed, 1 skipped, 0 cancelled" in result.stderr


@pytest.mark.sim
def test_verify_on_a_separate_dask_cluster_on_loopback_gives_the_same_rows(tmp_path: Path) -> None:
    with dask_cluster(tmp_path, workers=2) as address:
        result = orc("verify", *SUBSET[:2], "--scheduler", address, "--json", str(tmp_path / "r.json"))
    assert result.returncode == 0, result.stderr
    rows = json.loads((tmp_path / "r.json").read_text())["runs"]
    assert [row["program"] for row in rows] == list(SUBSET[:2])
    for row in rows:
        same_as_alone(row, alone(ROOT / row["program"]))
        assert row["verdict"] == "ok" and row["attempts"] == 1


@pytest.mark.slow
def test_verify_over_all_of_programs_gives_what_each_program_gives_alone(tmp_path: Path) -> None:
    result = orc("verify", "programs/", "--workers", "2", "--json", str(tmp_path / "r.json"))
    assert result.returncode in (0, 1), result.stderr
    rows = json.loads((tmp_path / "r.json").read_text())["runs"]
    assert sorted({row["program"] for row in rows}) == sorted(
        path.relative_to(ROOT).as_posix() for path in (ROOT / "programs").rglob("*") if path.suffix in (".rpl", ".orl"))
    with_process = 0
    for row in rows:
        summary = alone(ROOT / row["program"], row["robot"], margins=True)
        same_as_alone(row, summary)
        assert row["process"] == summary.get("process"), row["program"]
        with_process += summary.get("process") is not None
        near = (summary.get("margins") or {}).get("clearance")
        assert row["clearance_mm"] == (near["clearance_mm"] if near else None), row["program"]
        if near:
            assert row["clearance_at"] == f"{row['program']}:{near['line']}"
    assert with_process >= 5, "the application programs report their process outcomes"


@pytest.mark.sim
def test_verify_measures_clearance_in_the_cell_of_the_world_given(tmp_path: Path) -> None:
    (tmp_path / "cell.yaml").write_text(WORLD, encoding="utf-8")
    (tmp_path / "near.rpl").write_text(NEAR_THE_BLOCK, encoding="utf-8")
    result = orc("verify", "near.rpl", "--world", "cell.yaml", "--workers", "1", "--min-clearance", "100",
                 "--json", "r.json", "--junit", "j.xml", cwd=tmp_path)
    assert result.returncode == 1, result.stderr
    row = json.loads((tmp_path / "r.json").read_text())["runs"][0]
    assert row["clearance_bodies"] == ["link5", "block"] and row["clearance_at"] in ("near.rpl:3", "near.rpl:4")
    assert 75.0 < row["clearance_mm"] < 85.0
    assert row["reasons"] == [f"near miss: {row['clearance_mm']:.1f} mm, link5 to block at {row['clearance_at']} "
                              f"(t = {row['clearance_time_s']:.2f} s) (below 100 mm)"]
    case = ET.parse(tmp_path / "j.xml").getroot().find("testcase")
    assert case is not None
    properties = {p.get("name"): p.get("value") for p in case.iter("property")}
    assert properties["clearance_mm"] == f"{row['clearance_mm']:.3f}" and properties["clearance_at"] == row["clearance_at"]


@pytest.mark.sim
def test_process_outcomes_are_judged_against_the_header_and_the_baseline(tmp_path: Path) -> None:
    source = ROOT / "programs/online/thesis_3_1_deburring.rpl"
    header = "-- expect: burr_left_mm <= 0.2\n-- expect: bulges = 3\n"
    (tmp_path / "deburr.rpl").write_text(header + source.read_text(encoding="utf-8"), encoding="utf-8")
    (tmp_path / "deburr.sim.yaml").write_text(source.with_suffix(".sim.yaml").read_text(encoding="utf-8"))
    reference = alone(source)["process"]
    key = "deburr.rpl [irb2400]"
    baseline = {"version": 1, "runs": {key: {"cycle_time_s": 100.0, "process": {"bulges_within_tolerance": 3}}}}
    (tmp_path / "base.json").write_text(json.dumps(baseline), encoding="utf-8")
    result = orc("verify", "deburr.rpl", "--workers", "1", "--baseline", "base.json", "--json", "r.json",
                 "--save-baseline", "new.json", "--junit", "j.xml", cwd=tmp_path)
    assert result.returncode == 1, result.stderr
    row = json.loads((tmp_path / "r.json").read_text())["runs"][0]
    bulges = len(reference["bulges"])
    assert row["process"] == reference and row["process_figures"]["bulges"] == bulges == 2
    assert row["reasons"] == ["expected process bulges = 3 (header line 2), got 2",
                              "process bulges_within_tolerance: 2, 3 in the baseline"]
    saved = json.loads((tmp_path / "new.json").read_text())["runs"][key]["process"]
    assert saved == row["process_figures"] and saved["burr_left_mm"] <= 0.2
    properties = {p.get("name"): p.get("value") for p in ET.parse(tmp_path / "j.xml").getroot().iter("property")}
    assert properties["process.bulges"] == "2"


def test_ctrl_c_cancels_the_remaining_runs_and_keeps_the_finished_ones(tmp_path: Path) -> None:
    programs = [SUBSET[0], "programs/online/demo_thermal.rpl", "programs/online/demo_pallet.rpl"]
    process = subprocess.Popen([sys.executable, "-m", "orc_rpl", "verify", *programs, "--workers", "1",
                                "--json", str(tmp_path / "r.json")], cwd=ROOT, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    assert process.stderr is not None
    for line in process.stderr:
        if line.startswith("[1/3]"):
            break
    process.send_signal(signal.SIGINT)
    out, err = process.communicate(timeout=120)
    assert process.returncode == 130, err
    assert "interrupted" in err
    rows = json.loads((tmp_path / "r.json").read_text())["runs"]
    verdicts = [row["verdict"] for row in rows]
    assert verdicts.count("ok") == 1 and verdicts.count("cancelled") == 2
    assert "cancelled" in out


@pytest.mark.parametrize("argv, message", [
    (["--run-args=--bogus 1"], "--run-args: orc run says: unrecognized arguments: --bogus 1"),
    (["--run-args=--log x.npz"], "--run-args: --log is set by this command itself"),
    (["--robot", "r2d2"], "--robot: unknown robot 'r2d2'"),
    (["--baseline", "missing.json"], "--baseline: 'missing.json' does not exist"),
    (["--scheduler", "tcp://10.1.2.3:8786"], "plain TCP to another machine"),
])
def test_usage_errors_stop_before_anything_runs(argv: list[str], message: str) -> None:
    result = orc("verify", SUBSET[0], *argv)
    assert result.returncode == 2 and message in result.stderr and result.stdout == ""
