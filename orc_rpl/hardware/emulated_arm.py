"""The hardware room's emulated arm: a MuJoCo model of the robot whose joints are moved by the servos' own position loops."""

from __future__ import annotations

import math

import numpy as np

from orc_rpl.hardware.emulated_servo import EmulatedServo
from orc_rpl.plant.sim import SimCell
from orc_rpl.robot.robots import ROBOTS

#: The servo's own loop, as the emulator models it: a position loop commands a speed (at most the
#: motor's no-load speed, about 0.22 s per 60 deg for an STS3215 at 7.4 V), a velocity loop the torque,
#: saturated at the torque limit. It lags a moving reference by speed / POSITION_GAIN, as real bus
#: servos do, and droops by a count or two under the SO-101's weight.
POSITION_GAIN_1_S = 40.0
VELOCITY_GAIN_NM_S = 6.0
NO_LOAD_SPEED_RAD_S = 4.7
#: With torque off the gearbox (1:345) holds a joint against up to this torque: an unpowered SO-101 does
#: not fall under its own weight (an estimate; gravity needs at most about 0.35 N m on the SO-101).
GEARBOX_HOLD_NM = 0.6
GRIPPER_SPEED_RAD_S = 4.0          #: the gripper servo is modelled as a speed-limited follower
GRIPPER_RANGE_RAD = (-0.1745, 1.7453)


class EmulatedArm:
    """The robot's joints (servo ids 1..n) in MuJoCo and a gripper servo (id n+1) beside them."""

    def __init__(self, robot: str, servos: dict[int, EmulatedServo]) -> None:
        self.cell = SimCell(robot)
        self.spec = ROBOTS.get(robot)
        self.n = self.cell.n_joints
        self.servos = servos
        self.arm_servos = [servos[i + 1] for i in range(self.n)]
        self.gripper = servos.get(self.n + 1)
        self.model = self.arm_servos[0].model
        self._rad = self.model.rad_per_count()
        self._center = self.model.center_count
        self._tau_max = np.full(self.n, self.model.stall_torque_nm)
        self._gripper_q = 0.0
        self._gripper_qd = 0.0
        self._tau = np.zeros(self.n)
        self.hand: list[float] | None = None  #: joint targets of a hand moving the limp arm (calibration), or None
        self._held = self.cell.q  #: where the gearbox holds each limp joint
        self.publish()

    @property
    def time_s(self) -> float:
        return self.cell.time_s

    def count_to_rad(self, count: int) -> float:
        return (count - self._center) * self._rad

    def rad_to_count(self, q: float) -> int:
        return int(round(q / self._rad)) + self._center

    def step(self) -> None:
        """One millisecond: each servo's position loop, then the plant."""
        q, qd = self.cell.q, self.cell.qd
        tau = np.zeros(self.n)
        for i, servo in enumerate(self.arm_servos):
            if servo.torque_on:
                goal, limit = self.count_to_rad(servo.get("goal_position")), self._torque_limit(servo)
                self._held[i] = q[i]
            elif self.hand is not None:
                goal, limit = self.hand[i], self.model.stall_torque_nm  # a hand moves the limp joint
                self._held[i] = q[i]
            else:
                goal, limit = self._held[i], GEARBOX_HOLD_NM
            speed = max(-NO_LOAD_SPEED_RAD_S, min(NO_LOAD_SPEED_RAD_S, POSITION_GAIN_1_S * (goal - q[i])))
            tau[i] = max(-limit, min(limit, VELOCITY_GAIN_NM_S * (speed - qd[i])))
        self.cell.step(tau)
        if self.gripper is not None and self.gripper.torque_on:
            goal = self.count_to_rad(self.gripper.get("goal_position"))
            goal = min(max(goal, GRIPPER_RANGE_RAD[0]), GRIPPER_RANGE_RAD[1])
            step = GRIPPER_SPEED_RAD_S * self.cell.timestep_s
            moved = max(-step, min(step, goal - self._gripper_q))
            self._gripper_q += moved
            self._gripper_qd = moved / self.cell.timestep_s
        self._tau = self.cell.tau
        self.publish()

    def _torque_limit(self, servo: EmulatedServo) -> float:
        if "torque_limit" in servo.model.registers:
            return servo.get("torque_limit") / 1000.0 * self.model.stall_torque_nm
        return self.model.stall_torque_nm

    def publish(self) -> None:
        """Write the measured state into the servos' registers (12-bit encoder: whole counts)."""
        q, qd = self.cell.q, self.cell.qd
        tau = self._tau
        feetech = self.model.family == "feetech"
        for i, servo in enumerate(self.arm_servos):
            servo.put("present_position", self.rad_to_count(q[i]))
            servo.put("present_speed", int(round(qd[i] / self.model.speed_rad_s_per_unit)))
            share = tau[i] / self.model.stall_torque_nm
            current = int(round(abs(share) * self.model.stall_current_a / self.model.current_a_per_unit))
            if feetech:
                servo.put("present_load", int(round(1000.0 * share)))
            servo.put("present_current", current if feetech else int(math.copysign(current, share)))
            servo.put("moving", int(abs(qd[i]) > 0.01))
        if self.gripper is not None:
            self.gripper.put("present_position", self.rad_to_count(self._gripper_q))
            self.gripper.put("present_speed", int(round(self._gripper_qd / self.model.speed_rad_s_per_unit)))
