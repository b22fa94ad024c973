"""The hardware room's calibration procedure: the limp arm moved by hand, its counts recorded (as LeRobot users do)."""

from __future__ import annotations

import select
import sys
import time
from collections.abc import Callable
from typing import TextIO

from orc_rpl.hardware.bus import ServoBus
from orc_rpl.hardware.calibration import Calibration, GripperCalibration, JointCalibration, nominal
from orc_rpl.hardware.packets import BusError
from orc_rpl.robot.robots import RobotSpec

SAMPLE_PERIOD_S = 0.02


def scan(bus: ServoBus, ids: range) -> list[tuple[int, int]]:
    """(id, model number) of every servo that answers a ping."""
    found = []
    for servo_id in ids:
        model = bus.ping(servo_id)
        if model is not None:
            found.append((servo_id, model))
    return found


def _wait_for_enter(record_s: float | None, tick: Callable[[], None], out: TextIO) -> None:
    """Until Enter on standard input (or for record_s seconds), calling tick every sample period."""
    end = None if record_s is None else time.monotonic() + record_s
    while True:
        tick()
        if end is not None:
            if time.monotonic() >= end:
                return
            time.sleep(SAMPLE_PERIOD_S)
        elif select.select([sys.stdin], [], [], SAMPLE_PERIOD_S)[0]:
            sys.stdin.readline()
            return


def calibrate(bus: ServoBus, spec: RobotSpec, bus_name: str, record_s: float | None, out: TextIO) -> Calibration:
    """Torque off, the middle pose recorded as joint zero, then every joint's range as the hand moves it."""
    plan = nominal(spec, bus_name)
    model = plan.model
    ids = [j.servo_id for j in plan.joints] + ([plan.gripper.servo_id] if plan.gripper else [])
    for servo_id in ids:
        if all(bus.ping(servo_id) is None for _ in range(3)):
            raise BusError(f"servo {servo_id} does not answer on {bus.port} (orc bus scan lists the servos found)", servo_id)
    torque = model.reg("torque_enable")
    bus.sync_write(torque.address, 1, {i: b"\x00" for i in ids})
    position = model.reg("present_position")

    def read() -> dict[int, int]:
        replies = bus.sync_read(position.address, position.size, ids)
        return {i: position.decode(s.params) for i, s in replies.items()}

    def counts() -> dict[int, int]:
        for _ in range(2):  # nothing moves under power here: a lost reply is simply asked again
            try:
                return read()
            except BusError:
                pass
        return read()

    out.write(f"The torque of {spec.name}'s servos is off: the arm can be moved by hand.\n"
              "1. Put every joint in the middle of its range, the gripper closed"
              + (" (recording in 1 s)\n" if record_s is not None else ", then press Enter\n"))
    out.flush()
    if record_s is not None:
        time.sleep(1.0)
    else:
        _wait_for_enter(None, lambda: None, out)
    middle = counts()
    low, high = dict(middle), dict(middle)

    def sample() -> None:
        for servo_id, count in counts().items():
            low[servo_id], high[servo_id] = min(low[servo_id], count), max(high[servo_id], count)

    out.write("2. Move every joint slowly through its whole range"
              + (f" (recording for {record_s:g} s)\n" if record_s is not None else ", then press Enter\n"))
    out.flush()
    _wait_for_enter(record_s, sample, out)
    step = model.rad_per_count()
    joints = []
    for planned, lo, hi in zip(plan.joints, spec.q_min_rad, spec.q_max_rad):
        i, d = planned.servo_id, planned.direction
        # the middle pose is the middle of the model's range (joint zero itself when the range is symmetric)
        zero = middle[i] - d * int(round(0.5 * (lo + hi) / step))
        ends = sorted((d * (low[i] - zero) * step, d * (high[i] - zero) * step))
        joints.append(JointCalibration(i, zero, d, ends[0], ends[1]))
    gripper = None
    if plan.gripper is not None:
        gripper = GripperCalibration(plan.gripper.servo_id, middle[plan.gripper.servo_id], plan.gripper.direction)
    return Calibration(spec.name, bus_name, tuple(joints), gripper)
