"""The hardware room's calibration file: per joint the servo id, the count at joint zero, the direction and the range."""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from orc_rpl.errors import UsageError
from orc_rpl.hardware.registers import MODELS, ServoModel
from orc_rpl.robot.robots import RobotSpec

FORMAT = "orc_rpl servo calibration 1"
#: Robots built from serial-bus servos (the others are industrial arms: simulation only)
BUS_ROBOTS = ("so101",)


def check_bus_robot(robot: str, option: str = "--robot") -> None:
    """A UsageError unless `robot` is an arm on a servo bus."""
    if robot not in BUS_ROBOTS:
        raise UsageError(f"{option}: {robot!r} is not an arm on a servo bus (those are: {', '.join(BUS_ROBOTS)})")


@dataclass(frozen=True, slots=True)
class JointCalibration:
    """One joint on the bus: q = direction * (count - zero_count) * 2 pi / counts_per_rev, inside min..max."""

    servo_id: int
    zero_count: int        #: the servo's count at the model's joint zero
    direction: int         #: +1 or -1: whether the servo's count grows with the joint angle
    min_rad: float         #: the range the joint may use (limits are enforced before any motion)
    max_rad: float


@dataclass(frozen=True, slots=True)
class GripperCalibration:
    """The gripper's servo: angle = direction * (count - zero_count) * 2 pi / counts_per_rev (the program gives
    its OPEN and CLOSED angles)."""

    servo_id: int
    zero_count: int
    direction: int = 1


@dataclass(frozen=True, slots=True)
class Calibration:
    """A robot's servos as one bus sees them."""

    robot: str
    bus: str                                  #: "feetech" or "dynamixel"
    joints: tuple[JointCalibration, ...]
    gripper: GripperCalibration | None = None

    @property
    def model(self) -> ServoModel:
        return MODELS[self.bus]

    def to_counts(self, q_rad: Any) -> list[int]:
        scale = self.model.counts_per_rev / (2.0 * math.pi)
        return [j.zero_count + j.direction * int(round(q * scale)) for j, q in zip(self.joints, q_rad)]

    def to_rad(self, counts: list[int]) -> list[float]:
        step = 2.0 * math.pi / self.model.counts_per_rev
        return [j.direction * (c - j.zero_count) * step for j, c in zip(self.joints, counts)]

    def save(self, path: str | Path) -> Path:
        """Write the file; an existing file is never overwritten."""
        out = Path(path)
        if out.exists():
            raise UsageError(f"{out} exists; choose another file name (a calibration is never overwritten)")
        data = {"format": FORMAT, **asdict(self)}
        out.write_text(json.dumps(data, indent=2) + "\n", encoding="utf-8")
        return out


def nominal(spec: RobotSpec, bus: str) -> Calibration:
    """The calibration of an arm assembled as designed: servo i+1 drives joint i, joint zero at the middle count."""
    model = MODELS[bus]
    joints = tuple(JointCalibration(i + 1, model.center_count, 1, lo, hi)
                   for i, (lo, hi) in enumerate(zip(spec.q_min_rad, spec.q_max_rad)))
    n = len(joints)
    gripper = GripperCalibration(n + 1, model.center_count)
    return Calibration(spec.name, bus, joints, gripper)


def load(path: str | Path, spec: RobotSpec) -> Calibration:
    """Read a calibration file for `spec`; every mistake is a UsageError naming the file and the field."""
    source = Path(path)
    try:
        data = json.loads(source.read_text(encoding="utf-8"))
    except OSError as exc:
        raise UsageError(f"--calibration: cannot read {source}: {exc.strerror}") from None
    except json.JSONDecodeError as exc:
        raise UsageError(f"{source}:{exc.lineno}:{exc.colno}: not a calibration file (JSON): {exc.msg}") from None
    where = f"{source}"
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise UsageError(f"{where}: not a calibration file (expected \"format\": \"{FORMAT}\")")
    if data.get("robot") != spec.name:
        raise UsageError(f"{where}: calibrates robot {data.get('robot')!r}, not {spec.name!r}")
    if data.get("bus") not in MODELS:
        raise UsageError(f"{where}: \"bus\" must be one of {', '.join(MODELS)}")
    joints_data = data.get("joints")
    if not isinstance(joints_data, list) or len(joints_data) != len(spec.q_min_rad):
        raise UsageError(f"{where}: \"joints\" must list {len(spec.q_min_rad)} joints for {spec.name}")
    joints = []
    for i, item in enumerate(joints_data):
        try:
            joint = JointCalibration(int(item["servo_id"]), int(item["zero_count"]), int(item["direction"]),
                                     float(item["min_rad"]), float(item["max_rad"]))
        except (KeyError, TypeError, ValueError) as exc:
            raise UsageError(f"{where}: joint {i + 1}: needs servo_id, zero_count, direction, min_rad, max_rad ({exc})") from None
        if joint.direction not in (1, -1):
            raise UsageError(f"{where}: joint {i + 1}: direction must be 1 or -1")
        if not (math.isfinite(joint.min_rad) and math.isfinite(joint.max_rad) and joint.min_rad < joint.max_rad):
            raise UsageError(f"{where}: joint {i + 1}: min_rad must be below max_rad")
        joints.append(joint)
    gripper = None
    if data.get("gripper") is not None:
        g = data["gripper"]
        try:
            gripper = GripperCalibration(int(g["servo_id"]), int(g["zero_count"]), int(g.get("direction", 1)))
        except (KeyError, TypeError, ValueError) as exc:
            raise UsageError(f"{where}: gripper: needs servo_id and zero_count ({exc})") from None
        if gripper.direction not in (1, -1):
            raise UsageError(f"{where}: gripper: direction must be 1 or -1")
    ids = [j.servo_id for j in joints] + ([gripper.servo_id] if gripper else [])
    if len(set(ids)) != len(ids):
        raise UsageError(f"{where}: two joints use the same servo id")
    return Calibration(spec.name, data["bus"], tuple(joints), gripper)
