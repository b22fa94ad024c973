"""`orc bus scan|calibrate|emulate`: the servo bus of a real desktop arm, and an emulator to try it without one."""

from __future__ import annotations

import argparse
import math
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
    emulate.add_argument("--object-at", metavar="DEG", type=float, default=None,
                         help="an object between the gripper's jaws: the closing jaw meets it at this gripper angle "
                              "and squeezes it with the grip current (default: nothing to grip)")
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
        if hasattr(args, "robot"):
            from orc_rpl.hardware.calibration import check_bus_robot
            from orc_rpl.robot.robots import ROBOTS

            ROBOTS.get(args.robot)
            check_bus_robot(args.robot)
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
    if args.object_at is not None and not -10.0 <= args.object_at <= 100.0:
        raise UsageError(f"--object-at: the jaw travels from -10 to 100 deg, got {args.object_at:g}")
    object_rad = None if args.object_at is None else math.radians(args.object_at)
    serve(args.robot, args.bus, args.baud, faults, hand=args.hand, duration_s=args.duration_s, object_rad=object_rad)
    return 0


def _open(args: argparse.Namespace):  # -> ServoBus
    import os

    from orc_rpl.hardware.bus import ServoBus
    from orc_rpl.hardware.emulator import codec_for

    if not os.path.exists(args.port):
        raise UsageError(f"--port: no such device {args.port!r} (is the arm plugged in? is the emulator running?)")
    return ServoBus(args.port, codec_for(args.bus), args.baud)


def _scan(args: argparse.Namespace) -> int:
    from orc_rpl.hardware.calibrate import scan
    from orc_rpl.hardware.registers import MODELS

    first, _, last = args.ids.partition("-")
    try:
        ids = range(int(first), int(last or first) + 1)
    except ValueError:
        raise UsageError(f"--ids: expected FIRST-LAST such as 1-20, got {args.ids!r}") from None
    if not ids or ids.start < 0 or ids.stop > 254:
        raise UsageError(f"--ids: ids run from 0 to 253, got {args.ids!r}")
    bus = _open(args)
    found = scan(bus, ids)
    bus.close()
    names = {m.model_number: m.name for m in MODELS.values()}
    for servo_id, model in found:
        print(f"servo {servo_id}: model {model} ({names.get(model, 'unknown model')})")
    print(f"{len(found)} servo{'s' if len(found) != 1 else ''} found on {args.port} ({args.bus}, {args.baud} baud, "
          f"ids {ids.start}-{ids.stop - 1})")
    return 0 if found else 1


def _calibrate(args: argparse.Namespace) -> int:
    from pathlib import Path

    from orc_rpl.hardware.calibrate import calibrate
    from orc_rpl.robot.robots import ROBOTS

    spec = ROBOTS.get(args.robot)
    output = Path(args.output)
    if output.exists():
        raise UsageError(f"--output: {output} exists; choose another file name (a calibration is never overwritten)")
    if not output.resolve().parent.is_dir():
        raise UsageError(f"--output: the folder of {output} does not exist")
    if args.record_s is not None and not args.record_s > 0:
        raise UsageError("--record-s must be above 0")
    bus = _open(args)
    result = calibrate(bus, spec, args.bus, args.record_s, sys.stdout)
    bus.close()
    result.save(output)
    for k, joint in enumerate(result.joints):
        print(f"joint {k + 1}: servo {joint.servo_id}, zero at count {joint.zero_count}, range "
              f"{math.degrees(joint.min_rad):.1f}..{math.degrees(joint.max_rad):.1f} deg")
    print(f"wrote {output}; the torque stays off (the arm rests on its gearboxes)")
    return 0
