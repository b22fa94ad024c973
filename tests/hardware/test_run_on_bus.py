"""`orc run --port` on the emulated bus: programs move the arm; each injected fault stops it with a catchable DriveFault."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from orc_rpl.hardware.bus import ServoBus
from orc_rpl.hardware.emulator import codec_for
from tests.hardware.emulators import emulated_bus

pytestmark = pytest.mark.sim

#: connecting takes 41 goal-position sync writes (40 timed cycles and the hold): a fault @N with N a
#: little above fires in the middle of the program's first motions
DURING_FIRST_MOVE = 80

MOVES = """TOOL jaws = POSE(0, 0, 0, 0, 0, 0)
POS a = POSE(200mm, -60mm, 30mm, 0, 180deg, 0)
POS b = POSE(200mm, 60mm, 30mm, 0, 180deg, 0)
"""


def orc_run(tmp_path: Path, text: str, *options: str) -> tuple[int, str, str, dict]:
    program = tmp_path / "prog.rpl"
    program.write_text(text, encoding="utf-8")
    summary = tmp_path / "summary.json"
    done = subprocess.run([sys.executable, "-m", "orc_rpl", "run", str(program), "--robot", "so101",
                           "--summary-json", str(summary), *options], capture_output=True, text=True, timeout=120)
    data = json.loads(summary.read_text()) if summary.exists() else {}
    return done.returncode, done.stdout, done.stderr, data


@pytest.mark.parametrize("bus", ["feetech", "dynamixel"])
def test_a_program_moves_the_emulated_arm_to_its_positions(tmp_path: Path, bus: str) -> None:
    text = MOVES + "MOVE jaws TO a\nLMOVE jaws TO b WITH SPEED = 100mm/s\nPRINT ROUND(HERE.y / 1mm)\n"
    with emulated_bus("--robot", "so101", "--bus", bus) as port:
        code, out, err, summary = orc_run(tmp_path, text, "--port", port, "--bus", bus)
    assert code == 0, err
    assert out.split() == ["60"], (out, err)
    tcp = summary["final_tcp"]
    # the servos' own loops droop a count or two under the arm's weight: a millimetre at most
    assert abs(tcp["x_m"] - 0.200) < 1e-3 and abs(tcp["y_m"] - 0.060) < 1e-3 and abs(tcp["z_m"] - 0.030) < 1e-3, tcp
    assert "motion period" in err


@pytest.mark.parametrize("fault, servo", [("silent:3", 3), ("slow:2", 2), ("corrupt:4", 4), ("overload:3", 3),
                                          ("overheat:1", 1), ("unplugged", 1)])
def test_an_injected_fault_is_a_catchable_drive_fault_at_the_statement(tmp_path: Path, fault: str, servo: int) -> None:
    text = MOVES + ("TRY\n    MOVE jaws TO a\n    MOVE jaws TO b\nON DriveFault :\n    PRINT \"caught\"\nENDTRY\n"
                    "PRINT \"after\"\n")
    with emulated_bus("--robot", "so101", "--fault", f"{fault}@{DURING_FIRST_MOVE}") as port:
        code, out, err, _ = orc_run(tmp_path, text, "--port", port)
        if fault.startswith(("overload", "overheat")):
            check = ServoBus(port, codec_for("feetech"))
            torque = {i: check.read(i, 40, 1)[0] for i in range(1, 6)}
            check.close()
            # the alarmed servo is limp, the others hold
            assert torque == {i: int(i != servo) for i in range(1, 6)}, torque
    assert code == 0, err
    assert out.split() == ["caught", "after"], (out, err)


def test_an_uncaught_drive_fault_names_the_servo_and_the_statement(tmp_path: Path) -> None:
    text = MOVES + "MOVE jaws TO a\nMOVE jaws TO b\n"
    with emulated_bus("--robot", "so101", "--fault", f"silent:3@{DURING_FIRST_MOVE}") as port:
        code, _, err, summary = orc_run(tmp_path, text, "--port", port)
    assert code == 1
    assert summary["error"]["exception"] == "DriveFault"
    assert summary["error"]["line"] in (4, 5)
    assert "servo 3 (joint 3)" in summary["error"]["message"]
    assert "DriveFault: servo 3 (joint 3)" in err


def test_an_arm_that_is_not_there_is_refused_before_anything_moves(tmp_path: Path) -> None:
    code, _, err, _ = orc_run(tmp_path, MOVES + "MOVE jaws TO a\n", "--port", str(tmp_path / "ttyUSB9"))
    assert code == 2 and "--port: no such device" in err
    code, _, err, _ = orc_run(tmp_path, MOVES + "MOVE jaws TO a\n", "--calibration", "x.json")
    assert code == 2 and "--calibration needs --port" in err


@pytest.mark.parametrize("option, value, says", [
    ("--plant", "ideal", "--plant: a real arm (--port) is its own plant"),
    ("--seed", "3", "--seed: a real arm (--port) has no simulated noise to seed"),
])
def test_what_only_a_simulated_cell_has_is_refused_on_a_real_arm(tmp_path: Path, option: str, value: str,
                                                                  says: str) -> None:
    code, _, err, _ = orc_run(tmp_path, MOVES + "MOVE jaws TO a\n", "--port", str(tmp_path / "ttyUSB0"), option, value)
    assert code == 2 and says in err


def test_the_desk_arm_demo_runs_unchanged_on_the_simulated_cell_and_on_the_emulated_bus(tmp_path: Path) -> None:
    text = (Path(__file__).parents[2] / "programs" / "online" / "demo_desk_arm.rpl").read_text(encoding="utf-8")
    code, simulated, err, sim = orc_run(tmp_path, text)
    assert code == 0, err
    assert simulated.splitlines() == ["picked within 1.5 mm: TRUE", "holding a part: FALSE", "placed within 1.5 mm: TRUE",
                                      "gripper closed: FALSE"]
    with emulated_bus("--robot", "so101") as port:
        code, on_bus, err, bus = orc_run(tmp_path, text, "--port", port)
    assert code == 0, err
    assert on_bus == simulated, err
    assert sim["motions"] == bus["motions"]
    for axis in ("x_m", "y_m", "z_m"):
        assert abs(sim["final_tcp"][axis] - bus["final_tcp"][axis]) < 1e-3, (axis, sim["final_tcp"], bus["final_tcp"])


def test_scan_lists_the_servos_and_calibrate_records_zeros_and_ranges_that_run_then_enforces(tmp_path: Path) -> None:
    from orc_rpl.hardware.calibration import load
    from orc_rpl.robot.robots import ROBOTS

    orc = [sys.executable, "-m", "orc_rpl", "bus"]
    output = tmp_path / "so101.json"
    with emulated_bus("--robot", "so101", "--hand") as port:
        scan = subprocess.run([*orc, "scan", "--port", port, "--ids", "1-8"], capture_output=True, text=True, timeout=60)
        calibrate = subprocess.run([*orc, "calibrate", "--port", port, "--robot", "so101", "-o", str(output),
                                    "--record-s", "4.5"], capture_output=True, text=True, timeout=60)
        again = subprocess.run([*orc, "calibrate", "--port", port, "-o", str(output)], capture_output=True, text=True,
                               timeout=60)
    # the calibrated range of joint 1 made narrower by hand: a target beyond it is refused before any motion
    with emulated_bus("--robot", "so101") as port:
        data = json.loads(output.read_text())
        data["joints"][0]["min_rad"] = -0.1  # joint 1 turns the arm towards +y when negative
        narrow = tmp_path / "narrow.json"
        narrow.write_text(json.dumps(data))
        code, out, err, summary = orc_run(tmp_path, MOVES + "MOVE jaws TO a\nPRINT \"a\"\nMOVE jaws TO b\nPRINT \"b\"\n",
                                          "--port", port, "--calibration", str(narrow))
    assert scan.returncode == 0 and scan.stdout.splitlines()[:6] == [f"servo {i}: model 777 (STS3215)" for i in range(1, 7)]
    assert "6 servos found" in scan.stdout
    assert calibrate.returncode == 0, calibrate.stderr
    assert again.returncode == 2 and "never overwritten" in again.stderr
    spec = ROBOTS.get("so101")
    cal = load(output, spec)
    for joint, lo, hi in zip(cal.joints, spec.q_min_rad, spec.q_max_rad):
        assert abs(joint.zero_count - 2048) <= 2  # the emulated arm is assembled as designed
        # the emulated hand takes each joint to within 1 % of the ends of its range
        assert lo - 0.01 <= joint.min_rad <= lo + 0.04 * (hi - lo) and hi - 0.04 * (hi - lo) <= joint.max_rad <= hi + 0.01
    assert out.split() == ["a"] and code == 1
    # inverse kinematics keeps inside the calibrated ranges: the target is out of reach, at its statement
    assert summary["error"]["exception"] == "Unreachable" and summary["error"]["line"] == 6, summary["error"]


def test_features_that_need_joint_torques_are_refused_at_check_time_on_a_bus_arm(tmp_path: Path) -> None:
    port = tmp_path / "ttyUSB0"
    port.write_text("")
    program = Path(__file__).parents[2] / "programs" / "online" / "thesis_2_4_calibrate.rpl"
    done = subprocess.run([sys.executable, "-m", "orc_rpl", "run", str(program), "--robot", "so101", "--port", str(port)],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 2
    assert "CALIBRATE tunes the servo loops from joint torques; so101's bus servos report load and current" in done.stderr
    assert "nothing moved" in done.stderr


def test_ctrl_c_stops_the_motion_and_the_arm_holds_with_its_torque_on(tmp_path: Path) -> None:
    import signal
    import time

    program = tmp_path / "long.rpl"
    program.write_text(MOVES + "FOR i FROM 1 TO 20 DO\n    MOVE jaws TO a\n    MOVE jaws TO b\nENDFOR\n", encoding="utf-8")
    with emulated_bus("--robot", "so101") as port:
        run = subprocess.Popen([sys.executable, "-m", "orc_rpl", "run", str(program), "--robot", "so101", "--port", port],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        for line in run.stderr:  # wait until it has connected and started moving
            if "motion period" in line:
                break
        time.sleep(1.5)
        run.send_signal(signal.SIGINT)
        _, err = run.communicate(timeout=30)
        check = ServoBus(port, codec_for("feetech"))
        torque = [check.read(i, 40, 1)[0] for i in range(1, 6)]
        time.sleep(0.5)  # the servos' own loops settle the stop (gear play, droop); on a loaded machine the emulator lags
        first = [int.from_bytes(check.read(i, 56, 2), "little") for i in range(1, 6)]
        time.sleep(0.3)
        later = [int.from_bytes(check.read(i, 56, 2), "little") for i in range(1, 6)]
        check.close()
    assert run.returncode == 130, err
    assert "stopped by Ctrl-C; the arm holds its position (torque stays on)" in err
    assert torque == [1, 1, 1, 1, 1]
    # at rest, held with torque on (a falling arm moves hundreds of counts): each servo's own loop may still hunt
    # within its gear play, 0.3 deg = 3.4 counts of the 12-bit output encoder (the realistic plant's, as on the arm)
    assert max(abs(a - b) for a, b in zip(first, later)) <= 4, (first, later)
