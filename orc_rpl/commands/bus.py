"""`orc bus scan|calibrate|emulate`: the servo bus of a real desktop arm, and an emulator to try it without one."""

from __future__ import annotations

import argparse
import sys

from orc_rpl.errors import OrcError, UsageError


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    parser = subparsers.add_parser(
        "bus", help="serial servo buses: scan, calibrate, emulate",
        description="Work with the serial servo bus of a desktop arm (Feetech STS or Dynamixel 2.0): list the "
                    "servos, record a calibration, or run an emulated arm on a pseudo-terminal.")
    actions = parser.add_subparsers(dest="bus_command", metavar="ACTION")
    scan = actions.add_parser("scan", help="list the servos that answer on a port")
    _port_options(scan)
    scan.add_argument("--ids", metavar="FIRST-LAST", default="1-20", help="ids to ping (default 1-20)")
    calibrate = actions.add_parser("calibrate", help="record joint offsets and ranges into a calibration file")
    _port_options(calibrate)
    calibrate.add_argument("--robot", metavar="NAME", default="so101", help="robot model (default so101)")
    calibrate.add_argument("--output", "-o", metavar="FILE", default="calibration.json",
                           help="calibration file to write (default calibration.json); an existing file is kept")
    calibrate.add_argument("--record-s", metavar="SECONDS", type=float, default=None,
                           help="record the ranges for this long instead of until Enter")
    emulate = actions.add_parser("emulate", help="an emulated arm on a pseudo-terminal (prints its path)")
    emulate.add_argument("--robot", metavar="NAME", default="so101", help="robot model (default so101)")
    emulate.add_argument("--bus", choices=("feetech", "dynamixel"), default="feetech", help="protocol (default feetech)")
    emulate.add_argument("--baud", type=int, default=1_000_000, help="baud rate of the emulated wire (default 1000000)")
    emulate.add_argument("--fault", metavar="KIND[:ID][@N]", action="append", default=[],
                         help="inject a fault after the N-th goal-position sync write: unplugged, silent:ID, slow:ID, "
                              "corrupt:ID, overload:ID, overheat:ID (repeatable)")
    emulate.add_argument("--hand", action="store_true",
                         help="an emulated person moves the arm while its torque is off (for orc bus calibrate)")
    emulate.add_argument("--duration-s", type=float, default=None, help="stop after this many seconds")
    return parser


def _port_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--port", metavar="PORT", required=True, help="serial port (/dev/ttyUSB0, or the emulator's path)")
    parser.add_argument("--bus", choices=("feetech", "dynamixel"), default="feetech", help="protocol (default feetech)")
    parser.add_argument("--baud", type=int, default=1_000_000, help="baud rate (default 1000000)")


def _fail(message: str, code: int = 2) -> int:
    sys.stderr.write(f"orc bus: error: {message}\n")
    return code


def run(args: argparse.Namespace) -> int:
    if args.bus_command is None:
        return _fail("say what to do: orc bus scan|calibrate|emulate (orc bus --help)")
    try:
        if args.bus_command == "emulate":
            return _emulate(args)
        if args.bus_command == "scan":
            return _scan(args)
        return _calibrate(args)
    except UsageError as error:
        return _fail(str(error))
    except OrcError as error:
        return _fail(str(error), 1)
    except KeyboardInterrupt:
        return 0 if args.bus_command == "emulate" else 130


def _emulate(args: argparse.Namespace) -> int:
    from orc_rpl.hardware.emulator import FaultPlan
    from orc_rpl.hardware.serve import serve
    from orc_rpl.robot.robots import ROBOTS

    ROBOTS.get(args.robot)
    faults = tuple(FaultPlan.parse(text) for text in args.fault)
    serve(args.robot, args.bus, args.baud, faults, hand=args.hand, duration_s=args.duration_s)
    return 0


def _scan(args: argparse.Namespace) -> int:
    raise UsageError("scan is not available yet")


def _calibrate(args: argparse.Namespace) -> int:
    raise UsageError("calibrate is not available yet")
