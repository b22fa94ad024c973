"""The servo gripper on the emulated bus: a grip capped by its current stops on the object and says so."""

from __future__ import annotations

from pathlib import Path

import pytest

from orc_rpl.hardware.bus import ServoBus
from orc_rpl.hardware.emulator import codec_for
from orc_rpl.hardware.registers import CURRENT_BASED_POSITION_MODE, MODELS
from tests.hardware.emulators import emulated_bus
from tests.hardware.test_run_on_bus import orc_run

pytestmark = pytest.mark.sim

GRIP = """INSTALL jaws AS Gripper WITH SERVO = 6 WITH OPEN = 60deg WITH CLOSED = 2deg WITH GRIP_CURRENT = 0.4
jaws.Open
PRINT "open holding:", jaws.Holding
jaws.Close
PRINT "closed holding:", jaws.Holding, jaws.Closed
"""


def gripper_registers(port: str, bus: str) -> dict[str, int]:
    model = MODELS[bus]
    check = ServoBus(port, codec_for(bus))
    try:
        read = {name: model.reg(name) for name in ("present_position", "operating_mode", "goal_current")
                if name in model.registers}
        return {name: reg.decode(check.read(6, reg.address, reg.size)) for name, reg in read.items()}
    finally:
        check.close()


@pytest.mark.parametrize("bus", ["dynamixel", "feetech"])
def test_a_grip_on_an_object_stops_there_at_its_current_and_reports_it(tmp_path: Path, bus: str) -> None:
    with emulated_bus("--robot", "so101", "--bus", bus, "--object-at", "20") as port:
        code, out, err, _ = orc_run(tmp_path, GRIP, "--port", port, "--bus", bus)
        registers = gripper_registers(port, bus)
    assert code == 0, err
    assert out.splitlines() == ["open holding: FALSE", "closed holding: TRUE TRUE"], err
    model = MODELS[bus]
    # the jaw stands at the object (20 deg), short of CLOSED (2 deg), pressed in a little by the squeeze
    angle_deg = (registers["present_position"] - model.center_count) * 360 / model.counts_per_rev
    assert 15 < angle_deg <= 20.5, angle_deg
    if bus == "dynamixel":
        # current-based position control, its goal current the grip current (0.4 A in 2.69 mA units)
        assert registers["operating_mode"] == CURRENT_BASED_POSITION_MODE
        assert registers["goal_current"] == round(0.4 / model.current_a_per_unit)


def test_a_grip_on_nothing_closes_and_holds_nothing(tmp_path: Path) -> None:
    with emulated_bus("--robot", "so101", "--bus", "dynamixel") as port:
        code, out, err, _ = orc_run(tmp_path, GRIP, "--port", port, "--bus", "dynamixel")
    assert code == 0, err
    assert out.splitlines() == ["open holding: FALSE", "closed holding: FALSE TRUE"], err


def test_nothing_a_real_arm_says_calls_it_simulated(tmp_path: Path) -> None:
    program = ("TOOL jaws = POSE(0, 0, 0, 0, 0, 0)\nPOS a = POSE(200mm, -60mm, 30mm, 0, 180deg, 0)\n"
               "POS b = POSE(200mm, 60mm, 30mm, 0, 180deg, 0)\nMOVE jaws TO a\nMOVE jaws TO b\nMOVE jaws TO a\n")
    with emulated_bus("--robot", "so101") as port:
        code, _, err, summary = orc_run(tmp_path, program, "--port", port, "--timeout", "0.5")
    assert code == 1 and summary["status"] == "interrupted", err
    assert "simulat" not in err.lower(), err
    assert "cycle time:" in err and "(on the arm;" in err
    assert "interrupted by --timeout 0.5 s; the arm holds its position" in err
