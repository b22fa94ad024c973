"""ForceSensor: the cell's contact force with a bias and noise when simulated, a real gauge over a serial line."""

from __future__ import annotations

import textwrap

import pytest

from orc_rpl.executive.executive import Executive
from orc_rpl.executive.recording_robot import RecordingRobot
from orc_rpl.motion.force_sensor import SIM_BIAS_N, ForceEmulator
from orc_rpl.plant.processes.casting import CastingEdge
from orc_rpl.syntax.parser import parse
from orc_rpl.world.pose import Pose

TOOL = Pose(0.0, 0.0, 0.15)


def run(source: str, robot: RecordingRobot) -> tuple[Executive, list[str]]:
    out: list[str] = []
    source = textwrap.dedent(source).lstrip("\n")
    executive = Executive(parse(source, "force.rpl"), robot, path="force.rpl", source=source, output=out.append)
    executive.run()
    return executive, out


def test_a_simulated_gauge_reads_the_casting_contact_force_with_a_bias_and_noise() -> None:
    robot = RecordingRobot()
    edge = CastingEdge([(0.9, -0.2, 0.6), (0.9, 0.2, 0.6)], [], tcp=lambda: robot.tcp_pose(TOOL))
    robot.io.add_process(edge)
    executive, out = run("""
        TOOL grinder = POSE(0, 0, 150mm, 0, 0, 0)
        INSTALL Gauge AS ForceSensor WITH PORT = "sim"
        LMOVE grinder TO POSE(900mm, 0, 610mm, 0, 180deg, 0)
        PRINT ROUND(Gauge.Force / 1N, 2)
        LMOVE grinder TO POSE(900mm, 0, 599.6mm, 0, 180deg, 0)
        WAIT 8ms
        PRINT ROUND(Gauge.Force / 1N, 2)
        Gauge.Zero
        PRINT ROUND(Gauge.Force / 1N, 2)
        """, robot)
    assert executive.status == "finished", executive.report()
    free, pressed, tared = (float(x) for x in out)
    assert free == pytest.approx(SIM_BIAS_N, abs=1.0) and free != SIM_BIAS_N  # off the part: the bias and noise
    assert pressed == pytest.approx(edge.stiffness_n_m * 0.0004 + SIM_BIAS_N, abs=1.0)  # 0.4 mm into a 50 N/mm edge
    assert tared == pytest.approx(0.0, abs=1.0)
    again, _ = run("""
        TOOL grinder = POSE(0, 0, 150mm, 0, 0, 0)
        INSTALL Gauge AS ForceSensor WITH PORT = "sim"
        PRINT Gauge.Force
        """, RecordingRobot())
    assert again.status == "finished"


def test_the_simulated_gauge_repeats() -> None:
    readings = []
    for _ in range(2):
        _, out = run('INSTALL Gauge AS ForceSensor WITH PORT = "sim"\nPRINT Gauge.Force\nPRINT Gauge.Force\n', RecordingRobot())
        readings.append(out)
    assert readings[0] == readings[1] and readings[0][0] != readings[0][1]


def test_a_real_gauge_over_a_serial_line_and_its_lost_link() -> None:
    force = [12.5]
    device = ForceEmulator(lambda: force[0])
    try:
        robot = RecordingRobot()
        original = robot.tick

        def tick() -> None:  # the cable is cut during the WAIT
            original()
            device.lose_link()
        executive, out = run(f"""
            INSTALL Gauge AS ForceSensor WITH PORT = "{device.port}"
            PRINT Gauge.Force
            Gauge.Zero
            PRINT Gauge.Force
            """, robot)
        assert executive.status == "finished", executive.report()
        assert out == ["12.5 N", "0 N"] and device.requests == ["F?", "ZERO", "F?"]
        robot.tick = tick
        executive, out = run(f"""
            INSTALL Gauge AS ForceSensor WITH PORT = "{device.port}"
            WAIT 8ms
            TRY
                PRINT Gauge.Force
            ON SensorFault :
                PRINT "lost"
            ENDTRY
            """, robot)
        assert out == ["lost"], executive.report()
    finally:
        device.close()


def test_a_malformed_answer_is_a_sensor_fault() -> None:
    class Broken(ForceEmulator):
        def answer(self, request: str) -> str:
            return "F lots"
    device = Broken()
    try:
        executive, _ = run(f'INSTALL Gauge AS ForceSensor WITH PORT = "{device.port}"\nPRINT Gauge.Force\n', RecordingRobot())
    finally:
        device.close()
    assert executive.error is not None and executive.error.name == "SensorFault"
    assert "malformed answer 'F lots' to F?" in executive.error.message
