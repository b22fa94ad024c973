"""The pendant on the emulated SO-101: jog, teach and run on the bus, with manual mode's 250 mm/s cap."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pytest

from orc_rpl.commands import bus_robot
from orc_rpl.pendant.robot import PendantRobot
from orc_rpl.pendant.session import PendantSession
from tests.hardware.emulators import emulated_bus

pytestmark = pytest.mark.sim

PROGRAM = """TOOL jaws = POSE(0, 0, 0, 0, 0, 0)
POS over = POSE(200mm, 0, 40mm, 0, 180deg, 0)
POS far = POSE(180mm, 120mm, 20mm, 0, 180deg, 0)
MOVE jaws TO over
"""


def tcp_m(session: PendantSession) -> np.ndarray:
    pose = session.robot.tcp_pose(session.execution.tool_pose())
    return np.array([pose.x, pose.y, pose.z])


def hold_at_rest(session: PendantSession, cycles: int) -> None:
    """Motion cycles at the reference where the last move ended (the bus backend's droop correction at work)."""
    layer = session.robot.layer
    q_end = np.array(layer.reference_q(), dtype=float)[None]
    zero = np.zeros_like(q_end)
    for _ in range(cycles):
        layer.backend.advance(q_end, zero, zero)


def test_the_pendant_jogs_teaches_and_caps_manual_speed_on_the_emulated_arm(tmp_path: Path) -> None:
    path = tmp_path / "desk.rpl"
    path.write_text(PROGRAM, encoding="utf-8")
    with emulated_bus("--robot", "so101") as port:
        args = argparse.Namespace(robot="so101", port=port, calibration=None, bus=None, baud=1_000_000)
        session = PendantSession(path, robot=PendantRobot(bus_robot.connect(args, record=False)))
        try:
            session.execution.execute_text("MOVE jaws TO over")
            np.testing.assert_allclose(tcp_m(session), (0.200, 0.0, 0.040), atol=1e-3)  # a count or two of droop
            before = tcp_m(session)
            session.jogger.jog("world", "z", "-10mm")
            np.testing.assert_allclose((tcp_m(session) - before) * 1000, (0, 0, -10), atol=1.0)
            session.teach("low")
            session.editor.save()
            assert "POS low = POSE(200" in path.read_text(encoding="utf-8")
            assert session.execution.mode == "manual"
            session.execution.synchronous = False
            session.execution.execute_text("MOVE jaws TO far")
            # the references sent to the servos each motion cycle (the measured positions come at the wall
            # clock's irregular times on a busy machine: their differences are no speed measurement)
            layer = session.robot.layer
            last, peak, dt = layer.fk(layer.reference_q())[:3, 3], 0.0, session.robot.dt_s
            while session.execution.busy:
                session.execution.pump(1)
                now = layer.fk(layer.reference_q())[:3, 3]
                peak, last = max(peak, float(np.linalg.norm(now - last)) / dt), now
            assert peak <= 0.25 * 1.02, f"manual mode TCP speed {peak:.3f} m/s on the bus"
            # FINE arrives within SETTLED_COUNTS of every joint (its TCP up to about 1.5 mm off on this arm, at the
            # wall clock's mercy on a busy machine); held at rest, the droop correction then brings it within a
            # count or two: where the arm rests is what this asserts, as after the first move
            hold_at_rest(session, cycles=100)
            np.testing.assert_allclose(tcp_m(session), (0.180, 0.120, 0.020), atol=1e-3)
        finally:
            session.robot.layer.backend.hold()
            session.close()
