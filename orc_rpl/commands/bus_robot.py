"""The run command's real arm: `--port PORT [--calibration FILE]` wires a servo bus under the same motion layer."""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys
from typing import Any

import numpy as np

from orc_rpl.errors import Diagnostic, Location, UsageError

#: What needs joint torques, and why; a bus servo reports its load (PWM duty) and current, not torque.
TORQUE_MOTIONS = {"IDENTMOVE": "identifies parts from joint torques", "GRINDMOVE": "controls its force from joint torques"}
TORQUE_FUNCTIONS = {"IDENT": "identifies parts from joint torques", "CALIBRATE": "tunes the servo loops from joint torques"}


def add_options(parser: argparse.ArgumentParser) -> None:
    """--port, --calibration, --bus, --baud (real hardware, or the emulator's pseudo-terminal)."""
    parser.add_argument("--port", metavar="PORT", help="run on a real arm: its servo bus port (/dev/ttyUSB0, /dev/ttyACM0, "
                                                       "or the path orc bus emulate prints)")
    parser.add_argument("--calibration", metavar="FILE", help="calibration file from orc bus calibrate (with --port)")
    parser.add_argument("--bus", choices=("feetech", "dynamixel"), default=None,
                        help="servo protocol with --port (default: the calibration's, else feetech)")
    parser.add_argument("--baud", type=int, default=1_000_000, help="baud rate with --port (default 1000000)")


def check_options(args: argparse.Namespace) -> None:
    """Usage errors before anything moves."""
    sim = getattr(args, "sim", None)
    if sim is not None and args.port is not None:
        raise UsageError("--sim: a real arm (--port) has its own equipment; --sim describes the simulated cell's")
    if sim is not None and not os.path.isfile(sim):
        raise UsageError(f"--sim: {sim!r} is not a regular file" if os.path.exists(sim) else f"--sim: no such file {sim!r}")
    if args.port is None:
        for option in ("calibration", "bus"):
            if getattr(args, option) is not None:
                raise UsageError(f"--{option} needs --port (it describes a real arm's servo bus)")
        return
    from orc_rpl.hardware.calibration import check_bus_robot

    if getattr(args, "plant", None) is not None:
        raise UsageError("--plant: a real arm (--port) is its own plant; --plant chooses the simulated one")
    if getattr(args, "seed", None) is not None:
        raise UsageError("--seed: a real arm (--port) has no simulated noise to seed; --seed seeds the simulated plant's")
    check_bus_robot(args.robot, "--robot (with --port)")
    if not os.path.exists(args.port):
        raise UsageError(f"--port: no such device {args.port!r} (is the arm plugged in? is the emulator running?)")
    if args.calibration is not None and not os.path.isfile(args.calibration):
        raise UsageError(f"--calibration: no such file {args.calibration!r}")


def torque_diagnostics(program: Any, path: str, robot: str,
                       hint: str = "run it on the simulated cell (without --port)") -> list[Diagnostic]:
    """Check-time refusals on an arm on bus servos (real, or its realistic plant): features that need joint
    torques its servos cannot measure."""
    from orc_rpl.syntax import nodes

    found: list[Diagnostic] = []

    def refuse(node: Any, what: str, why: str) -> None:
        span = node.span
        found.append(Diagnostic(Location(path, span.line or 1, span.column or 1, span.end_line, span.end_column),
                                f"{what} {why}; {robot}'s bus servos report load and current, not joint torque",
                                hint=hint))

    for node in program.walk():
        if isinstance(node, nodes.Motion) and node.keyword.upper() in TORQUE_MOTIONS:
            refuse(node, node.keyword.upper(), TORQUE_MOTIONS[node.keyword.upper()])
        elif isinstance(node, nodes.Call) and isinstance(node.function, nodes.Name) \
                and node.function.id.upper() in TORQUE_FUNCTIONS:
            refuse(node, node.function.id.upper(), TORQUE_FUNCTIONS[node.function.id.upper()])
        elif isinstance(node, nodes.With) and node.name.id.upper() == "TUNING":
            refuse(node, "WITH TUNING", "sets servo gains that need joint torques")
        elif isinstance(node, nodes.Field) and isinstance(node.value, nodes.Name) and node.value.id.upper() == "ROBOT" \
                and node.name.id.upper() == "THERMAL":
            refuse(node, "ROBOT.Thermal", "estimates motor heating from joint torques")
    return found


def connect(args: argparse.Namespace, record: bool) -> Any:
    """A CellRobot whose motion layer drives the arm on args.port; prints the motion rate chosen."""
    from orc_rpl.executive.cell_robot import CellRobot
    from orc_rpl.hardware.backend import BusBackend
    from orc_rpl.hardware.bus import ServoBus
    from orc_rpl.hardware.calibration import load, nominal
    from orc_rpl.hardware.emulator import codec_for
    from orc_rpl.motion.ahead import PlanAhead
    from orc_rpl.motion.kinematics import Kinematics
    from orc_rpl.motion.layer import MotionLayer
    from orc_rpl.motion.planner import Planner
    from orc_rpl.motion.timing import preload
    from orc_rpl.motion.virtual import attach_recorder
    from orc_rpl.robot import ArmModel, solve_ik
    from orc_rpl.robot.robots import ROBOTS

    spec = ROBOTS.get(args.robot)
    if args.calibration is not None:
        cal = load(args.calibration, spec)
        if args.bus is not None and args.bus != cal.bus:
            raise UsageError(f"--bus {args.bus} differs from the calibration's bus {cal.bus}")
    else:
        cal = nominal(spec, args.bus or "feetech")
        sys.stderr.write(f"orc: no --calibration: assuming {spec.name} assembled as designed (orc bus calibrate "
                         "records the real offsets and ranges)\n")
    # The planner refuses what the calibration forbids: limits are enforced before any motion.
    lows = tuple(max(a, j.min_rad) for a, j in zip(spec.q_min_rad, cal.joints))
    highs = tuple(min(b, j.max_rad) for b, j in zip(spec.q_max_rad, cal.joints))
    home = tuple(min(max(h, lo), hi) for h, lo, hi in zip(spec.home_q_rad, lows, highs))
    arm = ArmModel(dataclasses.replace(spec, q_min_rad=lows, q_max_rad=highs, home_q_rad=home))
    backend = BusBackend(ServoBus(args.port, codec_for(cal.bus), args.baud), cal)
    layer = MotionLayer(Kinematics(arm, solve_ik), backend, backend.servo_period_s)
    # the next move is planned on a worker thread over an arm model of its own: planning never delays a bus cycle
    layer.ahead = PlanAhead(lambda: Planner(Kinematics(ArmModel(arm.spec), solve_ik), layer.dt_s, layer.sub), paced=True)
    preload()
    if record:
        attach_recorder(layer)
    sys.stderr.write(f"orc: {spec.name} on {args.port} ({cal.model.name}, {cal.bus}): motion period "
                     f"{1000 * backend.servo_period_s:.0f} ms (measured bus cycle: median "
                     f"{1000 * float(np.median(backend.cycle_times_s)):.2f} ms)\n")
    return CellRobot(layer)


def stop_and_hold(robot: Any) -> None:
    """Ctrl-C on a real arm: brake on the path, then hold where it stopped (torque stays on: the arm does not fall)."""
    layer = robot.layer
    try:
        if not layer.idle():
            layer.stop_move(by="Ctrl-C")
            layer.run_until_idle(timeout_s=2.0)
    except KeyboardInterrupt:
        pass  # a second Ctrl-C: hold at once
    finally:
        layer.backend.hold()
    sys.stderr.write("orc run: stopped by Ctrl-C; the arm holds its position (torque stays on)\n")
