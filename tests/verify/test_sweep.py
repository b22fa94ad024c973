"""`orc sweep`: a grid of CONST values run in parallel, written as CSV, JSON lines and a plot."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest
from matplotlib import image

from orc_rpl.cli import main
from orc_rpl.commands.many_runs import run_accepts
from orc_rpl.errors import UsageError
from orc_rpl.verify.plot import plot_outcomes
from orc_rpl.verify.sweep import Variation, grid, record_of, split_values
from orc_rpl.verify.task import RunOutcome
from tests.verify.conftest import alone, orc

PROGRAM = ("-- One motion whose speed and height are parameters.\nCONST speed = 0.5mps\nCONST height = 700mm\n"
           "TOOL probe = POSE(0, 0, 100mm, 0, 0, 0)\n"
           "LMOVE probe TO POSE(900mm, -200mm, height, 0, 180deg, 0) WITH SPEED = speed\n")


def test_values_split_at_top_level_commas() -> None:
    assert split_values("p=POSE(1, 2, 3, 0, 0, 0),3mm") == ("p", ("POSE(1, 2, 3, 0, 0, 0)", "3mm"))
    with pytest.raises(UsageError, match="an empty value"):
        split_values("v=1,,2")


def test_the_grid_is_every_combination_first_parameter_slowest() -> None:
    light = Variation("light", ("--plant", "ideal"))
    points = grid(["a=1,2", "b=x,y"], 2, [light])
    assert len(points) == 8
    assert [p.settings for p in points[:3]] == [(("a", "1"), ("b", "x"))] * 2 + [(("a", "1"), ("b", "y"))]
    assert [p.seed for p in points[:2]] == [0, 1] and points[0].variation == light


@pytest.mark.sim
def test_sweep_writes_one_row_per_point_identical_to_orc_run_set(tmp_path: Path) -> None:
    program = tmp_path / "speed.rpl"
    program.write_text(PROGRAM, encoding="utf-8")
    result = orc("sweep", str(program), "--set", "speed=0.25mps,0.5mps,1mps", "--set", "height=600mm,700mm",
                 "--workers", "2", "--out", str(tmp_path / "out"), cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    with (tmp_path / "out.csv").open(encoding="utf-8") as stream:
        rows = list(csv.DictReader(stream))
    lines = [json.loads(line) for line in (tmp_path / "out.jsonl").read_text().splitlines()]
    assert [(r["speed"], r["height"]) for r in rows] == [(s, h) for s in ("0.25mps", "0.5mps", "1mps")
                                                          for h in ("600mm", "700mm")]
    assert [line["cycle_time_s"] for line in lines] == [float(r["cycle_time_s"]) for r in rows]
    reference = alone(program)  # the program's own values: speed 0.5 m/s, height 700 mm
    assert lines[3]["cycle_time_s"] == reference["cycle_time_s"] and lines[3]["status"] == "finished"
    at_700 = [line["cycle_time_s"] for line in lines if line["height"] == "700mm"]
    assert at_700[0] > at_700[1] > at_700[2]  # faster motion, shorter cycle
    assert (tmp_path / "out.png").stat().st_size > 10_000
    again = orc("sweep", str(program), "--set", "speed=1mps", "--out", str(tmp_path / "out"), cwd=tmp_path)
    assert again.returncode == 2 and "already exist" in again.stderr  # nothing the user has is overwritten


def test_sweep_refuses_a_const_the_program_lacks_before_running(tmp_path: Path) -> None:
    program = tmp_path / "speed.rpl"
    program.write_text(PROGRAM, encoding="utf-8")
    result = orc("sweep", str(program), "--set", "sped=1mps,2mps", "--workers", "1", cwd=tmp_path)
    assert result.returncode == 2
    assert "no top-level CONST 'sped' (its CONSTs: height, speed)" in result.stderr
    assert not list(tmp_path.glob("sweep-*"))


def test_seeds_need_an_orc_run_with_seed(tmp_path: Path) -> None:
    program = tmp_path / "speed.rpl"
    program.write_text(PROGRAM, encoding="utf-8")
    if run_accepts("--seed"):
        pytest.skip("orc run has --seed here: seeds are swept (test_seeds_are_swept_as_orc_run_seed)")
    result = orc("sweep", str(program), "--set", "speed=1mps", "--seeds", "3", cwd=tmp_path)
    assert result.returncode == 2 and "orc run of this installation has no --seed option yet" in result.stderr


def test_plant_variations_are_checked_against_orc_run(tmp_path: Path) -> None:
    program = tmp_path / "speed.rpl"
    program.write_text(PROGRAM, encoding="utf-8")
    (tmp_path / "v.yaml").write_text("variations:\n  - {name: slow, run-args: '--speed-override 50%'}\n"
                                     "  - {name: bad, run-args: '--no-such-option 1'}\n", encoding="utf-8")
    result = orc("sweep", str(program), "--set", "speed=1mps", "--plant-variation", str(tmp_path / "v.yaml"),
                 cwd=tmp_path)
    assert result.returncode == 2
    assert "variation 'bad'" in result.stderr and "--no-such-option" in result.stderr


@pytest.mark.sim
def test_seeds_are_swept_as_orc_run_seed(tmp_path: Path) -> None:
    if not run_accepts("--seed"):
        pytest.skip("orc run of this installation has no --seed option yet")
    program = tmp_path / "speed.rpl"
    program.write_text(PROGRAM, encoding="utf-8")
    result = orc("sweep", str(program), "--set", "speed=0.5mps", "--seeds", "2", "--workers", "2",
                 "--out", str(tmp_path / "seeds"), cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    lines = [json.loads(line) for line in (tmp_path / "seeds.jsonl").read_text().splitlines()]
    assert [line["seed"] for line in lines] == [0, 1]
    for line in lines:
        summary = tmp_path / f"alone-{line['seed']}.json"
        assert main(["run", str(program), "--seed", str(line["seed"]), "--summary-json", str(summary)]) == 0
        assert line["cycle_time_s"] == json.loads(summary.read_text())["cycle_time_s"]


def test_a_process_section_becomes_columns_of_the_table() -> None:
    summary = {"status": "finished", "cycle_time_s": 2.0, "motions": 3, "warnings": [], "error": None,
               "process": {"identifications": [{"part": "heavy", "payload_kg": 4.98}], "welds": []}}
    record = record_of(0, grid(["m=1"], None, [])[0], RunOutcome(0, summary, "", ""), 1, None)
    assert record["m"] == "1" and record["status"] == "finished" and record["cycle_time_s"] == 2.0
    assert record["process.identifications.0.part"] == "heavy"
    assert record["process.identifications.0.payload_kg"] == 4.98
    assert record["figure.parts"] == "heavy" and record["clearance_mm"] is None  # no margins section: not measured


def test_each_outcome_chosen_gets_its_panel(tmp_path: Path) -> None:
    records = [{"v": v, "seed": seed, "cycle_time_s": 2.0 / float(v[:-3]) + seed, "clearance_mm": 10.0 * seed,
                "status": "finished"} for v in ("1mps", "2mps") for seed in (0, 1)]
    records.append({"v": "3mps", "seed": 0, "cycle_time_s": None, "status": "failed"})
    assert plot_outcomes(records, "v", ["cycle_time_s"], [], tmp_path / "one.png", "t") == 4
    assert plot_outcomes(records, "v", ["cycle_time_s", "clearance_mm"], [], tmp_path / "two.png", "t") == 8
    one, two = image.imread(tmp_path / "one.png"), image.imread(tmp_path / "two.png")
    assert two.shape[0] > 1.7 * one.shape[0] and two.shape[1] == one.shape[1]


def test_the_margins_become_columns_with_the_line_of_their_motion() -> None:
    near = {"clearance_mm": 31.5, "file": "p.rpl", "line": 7, "column": 1, "robot_body": "link6", "obstacle": "fence",
            "time_s": 2.0}
    joint = {"joint_margin_deg": 9.5, "joint": 5, "file": "p.rpl", "line": 4, "column": 1}
    summary = {"status": "finished", "cycle_time_s": 2.0, "motions": 3, "warnings": [], "error": None,
               "margins": {"clearance": near, "joint_margin": joint, "motions": []}}
    record = record_of(0, grid(["m=1"], None, [])[0], RunOutcome(0, summary, "", ""), 1, None)
    assert (record["clearance_mm"], record["clearance_line"], record["clearance_bodies"]) == (31.5, 7, "link6/fence")
    assert (record["joint_margin_deg"], record["joint_margin_line"]) == (9.5, 4)


@pytest.mark.sim
def test_a_sweep_over_cell_variations_alone_tells_every_part_or_holds_it(tmp_path: Path) -> None:
    # IDENTMOVE's robustness as docs/verify.md shows it: the part under the gripper varied through --sim files,
    # no --set; the plot's x axis is the variation
    root = Path(__file__).resolve().parents[2]
    result = orc("sweep", str(root / "programs/online/thesis_2_5_identmove.rpl"), "--plant-variation",
                 str(root / "benchmarks/sweeps/ident_parts.yaml"), "--workers", "2", "--out", str(tmp_path / "ident"),
                 "--outcome", "process.identifications.1.payload_kg", cwd=root)
    assert result.returncode == 0, result.stderr
    rows = {row["variation"]: row for row in map(json.loads, (tmp_path / "ident.jsonl").read_text().splitlines())}
    right = {"nothing": "NoObject", "nut-0.3kg": "Nut", "heavy-nut-0.45kg": "Nut", "bolt-0.9kg": "Bolt"}
    assert set(rows) == set(right)
    for name, part in right.items():
        told = rows[name]["process.identifications.1.part"]
        assert rows[name]["status"] == "finished" and told in (part, ""), (name, told)  # "": uncertain, held
    assert (tmp_path / "ident.png").stat().st_size > 0


def test_a_sweep_needs_something_to_sweep(tmp_path: Path) -> None:
    program = tmp_path / "speed.rpl"
    program.write_text(PROGRAM, encoding="utf-8")
    result = orc("sweep", str(program), cwd=tmp_path)
    assert result.returncode == 2 and "give at least one --set NAME=V1,V2,..., --seeds N or --plant-variation FILE" in result.stderr
