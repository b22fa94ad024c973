"""`orc run` shows what the processes achieved: the summary's `process` section, its lines, the recorded process signals, the plot."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from orc_rpl.cli import main
from orc_rpl.executive.process_report import process_lines
from orc_rpl.signals.recording import Recording

ROOT = Path(__file__).resolve().parents[2]
PROGRAMS = ROOT / "programs" / "online"


def _run(program: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], *extra: str) -> tuple[int, dict, str, str]:
    summary = tmp_path / "summary.json"
    code = main(["run", str(program), "--summary-json", str(summary), *extra])
    out, err = capsys.readouterr()
    return code, json.loads(summary.read_text()), out, err


@pytest.mark.sim
def test_spot_welds_are_in_the_summary_with_their_quality(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, result, out, err = _run(PROGRAMS / "demo_spot_welding.rpl", tmp_path, capsys)
    assert code == 0, err
    welds = result["process"]["welds"]
    assert len(welds) == 6 and all(w["good"] for w in welds)
    assert all(w["speed_m_s"] < 0.02 and w["offset_m"] < 0.001 and len(w["position_m"]) == 3 for w in welds)
    assert [w["time_s"] for w in welds] == sorted(w["time_s"] for w in welds)
    assert "process: welds: 6 good of 6" in err
    assert out.splitlines() == ["spots welded: 6 of 6"]


@pytest.mark.sim
def test_grinding_is_logged_plotted_and_summarised(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    log, plot = tmp_path / "run.npz", tmp_path / "run.png"
    # the thesis program with a force flange on its grinder (without one the arm presses: test_deburring_arm.py)
    program = tmp_path / "thesis_2_1_grindmove.rpl"
    grinder = "INSTALL grinder AS Grinder WITH SPINDLE = DigOut[5]\n"
    source = (PROGRAMS / program.name).read_text(encoding="utf-8")
    assert grinder in source
    program.write_text(source.replace(grinder, grinder[:-1] + " WITH FORCE_IN = AnalogIn[8] WITH STROKE = AnalogOut[8]\n"),
                       encoding="utf-8")
    shutil.copy((PROGRAMS / program.name).with_suffix(".sim.yaml"), program.with_suffix(".sim.yaml"))
    code, result, _, err = _run(program, tmp_path, capsys, "--log", str(log), "--plot", str(plot))
    assert code == 0, err
    (bulge,) = result["process"]["bulges"]
    # the casting's 1.4 mm bulge: one force-controlled pass leaves at least 1 mm of it (the premise of GRINDMOVE)
    assert 0.001 <= bulge["caught_height_m"] <= 0.0014 and bulge["within_tolerance"] and bulge["left_m"] <= 0.0002
    assert len(bulge["pass_heights_m"]) >= 1 and bulge["pass_heights_m"][-1] == bulge["left_m"]
    assert "process: bulge 1.2" in err and "mm caught at s = 0.2" in err
    recording = Recording.from_npz(log)
    assert recording["tool_tcp"].shape == recording["tcp"].shape
    force = recording["process.force_n"]
    grinding = ~np.isnan(force)
    assert grinding.any() and (~grinding).any()  # NaN before the grinder touches the edge
    assert np.nanmax(np.abs(force[grinding][100:] - 30.0)) < 6.0
    assert np.all(np.isnan(recording["process.payload_kg"]))
    assert plot.stat().st_size > 10_000


@pytest.mark.sim
def test_an_uncaught_weld_fault_is_a_failed_run_with_a_process_warning(tmp_path: Path,
                                                                      capsys: pytest.CaptureFixture[str]) -> None:
    program = tmp_path / "strict.rpl"
    program.write_text((PROGRAMS / "demo_spot_welding.rpl").read_text().replace(
        "WITH WELD_TIME = 150ms", "WITH WELD_TIME = 150ms WITH MAX_SPEED = 1mm/s"))
    shutil.copy(PROGRAMS / "demo_spot_welding.sim.yaml", tmp_path / "strict.sim.yaml")
    code, result, _, err = _run(program, tmp_path, capsys)
    assert code == 1 and result["status"] == "failed" and result["error"]["exception"] == "WeldFault"
    (fault,) = result["process"]["faults"]
    assert fault["exception"] == "WeldFault" and not fault["caught"]
    assert any(w["message"].startswith("process fault not caught: WeldFault") for w in result["warnings"])
    assert result["process"]["welds"][-1]["good"] is False
    assert "bad weld at t = " in err


def test_a_program_without_processes_has_no_process_section(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    program = tmp_path / "plain.rpl"
    program.write_text('PRINT "hello"\n')
    code, result, _, _ = _run(program, tmp_path, capsys)
    assert code == 0 and "process" not in result


def test_a_bulge_ground_a_hair_below_the_edge_reads_0_00_mm_not_minus_0_00() -> None:
    section = {"welds": [], "seams": [], "identifications": [], "tunings": [], "faults": [],
               "bulges": [{"caught_height_m": 7.6e-4, "s0": 0.32, "s1": 0.37, "left_m": -2e-6,
                           "pass_heights_m": [4e-4, 0.0], "within_tolerance": True}]}
    assert process_lines(section) == ["bulge 0.76 mm caught at s = 0.32..0.37, ground to 0.00 mm in 2 passes"]
