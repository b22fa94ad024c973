"""GRINDMOVE without a force flange (thesis 2.1, 3.4): the arm presses and reads the force from its own motor torques."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from orc_rpl.application.features import deburring_behaviour as db
from orc_rpl.application.standard_behaviour import runtime_registry
from orc_rpl.cli import main
from orc_rpl.executive.cell_robot import CellRobot
from orc_rpl.executive.executive import Executive
from orc_rpl.plant.processes.casting import Bulge, CastingEdge
from orc_rpl.syntax.parser import parse
from tests.executive.support import execute

ROOT = Path(__file__).resolve().parents[2]
EDGE = [(0.9, -0.2, 0.6), (0.9, 0.2, 0.6)]
PROGRAM = """TOOL grinder = POSE(0, 0, 150mm, 0, 0, 0)
INSTALL grinder AS Grinder WITH SPINDLE = DigOut[5]
PATH edge = [POSE(900mm, -200mm, 600mm, 0, 180deg, 0), POSE(900mm, 0, 600mm, 0, 180deg, 0), POSE(900mm, 200mm, 600mm, 0, 180deg, 0)]
GRINDMOVE grinder ALONG edge WITH VELOCITY = 100mm/s WITH FORCE = {force} WITH GRINDING = GrindingPars(tolerance = 0.2mm, max_passes = {passes})
"""
#: The casting's force goes to an input nobody reads: the arm has no force sensor.
UNREAD_INPUT = 3


def grind(bulges: list[Bulge], stiffness_n_m: float = 5e4, force: str = "30N", passes: int = 4,
          casting: bool = True) -> tuple[Executive, CastingEdge, db.GrindLog]:
    """thesis_2_1's edge on the realistic plant (or nothing there), its contact force acting on the arm."""
    robot = CellRobot.virtual(plant="realistic")
    source = PROGRAM.format(force=force, passes=passes)
    registry, logs = runtime_registry(), []

    def logged(call: Any) -> Any:
        logs.append(db.GrindLog())
        return db.grindmove(call, logs[-1])
    registry.motions["GRINDMOVE"] = dataclasses.replace(registry.motions["GRINDMOVE"], execute=logged)
    executive = Executive(parse(source, "arm.rpl"), robot, registry, path="arm.rpl", source=source,
                          output=lambda line: None)
    edge = CastingEdge(EDGE, bulges, tcp=lambda: robot.tcp_pose(executive.machine.last_tool),
                       force_in=UNREAD_INPUT, stiffness_n_m=stiffness_n_m, push=robot.push_on_arm)
    if casting:
        robot.io.add_process(edge)
    executive.run()
    (log,) = logs
    return executive, edge, log


@pytest.mark.sim
def test_the_arm_catches_a_bulge_by_its_own_signals_and_grinds_it_off() -> None:
    executive, edge, log = grind([Bulge(0.1, 0.14, 0.0014)])
    assert executive.status == "finished", executive.report()
    (bulge,) = log.bulges
    assert 0.24 <= bulge.s0 < bulge.s1 <= 0.4 and bulge.height_m > 0.0008  # the bulge is at s = 0.25..0.35
    assert bulge.within_tolerance and 1 <= len(bulge.passes) <= 4
    assert edge.max_height_m() <= 0.0002 and log.warnings == []


@pytest.mark.sim
def test_a_clean_casting_has_no_false_bulge() -> None:
    executive, edge, log = grind([])
    assert executive.status == "finished", executive.report()
    assert log.bulges == [] and log.warnings == []
    pressing = np.array(log.samples)[:, 4]
    assert np.median(pressing) == pytest.approx(30.0, abs=3.0)  # the arm pressed with the commanded force


@pytest.mark.sim
def test_a_five_times_stiffer_casting_is_still_ground_within_the_tolerance() -> None:
    executive, edge, log = grind([Bulge(0.1, 0.14, 0.0014)], stiffness_n_m=2.5e5)
    assert executive.status == "finished", executive.report()
    assert len(log.bulges) == 1 and log.bulges[0].within_tolerance and edge.max_height_m() <= 0.0002


@pytest.mark.sim
def test_a_contact_far_stiffer_than_the_loop_allows_raises_process_fault() -> None:
    executive, edge, _ = grind([Bulge(0.1, 0.14, 0.0014)], stiffness_n_m=5e6)
    assert executive.status == "failed" and executive.error is not None
    assert "ProcessFault" in executive.report() and "the force loop is unstable" in executive.report()


@pytest.mark.sim
def test_a_bigger_bulge_raises_burr_left_and_more_force_and_passes_grind_it() -> None:
    executive, edge, log = grind([Bulge(0.1, 0.14, 0.003)])
    assert executive.status == "failed" and "BurrLeft" in executive.report(), executive.report()
    assert edge.max_height_m() > 0.0002  # the burr really is left, and said so
    executive, edge, log = grind([Bulge(0.1, 0.14, 0.003)], force="40N", passes=8)
    assert executive.status == "finished", executive.report()
    assert log.bulges[0].within_tolerance and edge.max_height_m() <= 0.0002


def test_a_robot_without_motor_torques_to_read_needs_a_force_flange() -> None:
    executive = execute(PROGRAM.format(force="30N", passes=4))
    assert executive.status == "failed"
    assert "presses with the arm" in executive.report() and "FORCE_IN" in executive.report()


@pytest.mark.sim
def test_an_edge_the_arm_never_touches_is_a_warning_not_a_silent_finish() -> None:
    executive, _, log = grind([], casting=False)
    assert executive.status == "finished", executive.report()
    assert log.bulges == [] and "the arm felt no contact force along the whole path" in log.warnings[0]


@pytest.mark.sim
def test_grinding_through_the_arm_feels_the_casting_on_elastic_gears(capsys: pytest.CaptureFixture[str],
                                                                      tmp_path: Path) -> None:
    # the arm's force estimate takes the motors' acceleration only below the gears' anti-resonance: with the rotors'
    # own shaking read as contact force, the loop rang and the arm felt nothing along the whole path
    summary = tmp_path / "summary.json"
    code = main(["run", str(ROOT / "programs/online/thesis_2_1_grindmove.rpl"), "--plant", "elastic-gears",
                 "--summary-json", str(summary)])
    out, err = capsys.readouterr()
    assert code == 0, err
    result = json.loads(summary.read_text())
    assert result["status"] == "finished" and result["warnings"] == []
    assert "bulges caught: 1" in out


@pytest.mark.sim
def test_the_arm_force_estimate_averages_the_acceleration_over_the_gears_anti_resonance_only_on_elastic_gears() -> None:
    from orc_rpl.application.features.gears import gear_period_cycles

    q = np.array([0.0, 0.3, 0.2, 0.0, 1.0, 0.0])
    assert gear_period_cycles(CellRobot.virtual(), q) == 1
    window = gear_period_cycles(CellRobot.virtual(plant="elastic-gears"), q)
    assert 20 <= window <= 40  # j2's anti-resonance, about 55 rad/s: 0.11 s of 4 ms cycles
