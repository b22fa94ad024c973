"""The hardware room's emulated arm: the servos' registers over the realistic plant of the robot on bus servos."""

from __future__ import annotations

import math

import numpy as np

from orc_rpl.hardware.droop import DroopCorrection
from orc_rpl.hardware.emulated_servo import EmulatedServo
from orc_rpl.hardware.registers import CURRENT_BASED_POSITION_MODE
from orc_rpl.plant.servo_arm import ServoArmCell
from orc_rpl.plant.servo_gripper import GripperServo, ServoGripper

#: The overheating alarm bit (of STS "status" and Dynamixel "hardware_error").
OVERHEAT_BIT = 4


class EmulatedArm:
    """The robot's joints (servo ids 1..n) in the servo-arm plant and a gripper servo (id n+1) beside them.

    Every step the servos' goals, torque enables and torque or current limits go from the registers
    into the plant (plant.servo_arm: the servos' own position loops, gear play, 12-bit encoders,
    winding temperature), and what the plant's servos report comes back into the registers.
    """

    def __init__(self, robot: str, servos: dict[int, EmulatedServo], object_rad: float | None = None) -> None:
        self.cell = ServoArmCell(robot)
        self.n = self.cell.n_joints
        self.servos = servos
        self.arm_servos = [servos[i + 1] for i in range(self.n)]
        self.gripper = servos.get(self.n + 1)
        self.model = self.arm_servos[0].model
        self._rad = self.model.rad_per_count()
        self._center = self.model.center_count
        plant = self.cell.plant
        self.jaw = ServoGripper(GripperServo(self.model.stall_torque_nm, self.model.stall_current_a,
                                             plant.no_load_speed_rad_s, self._rad), object_rad=object_rad)
        self.hand: list[float] | None = None  #: joint targets of a hand moving the limp arm (calibration), or None
        self._hand_eye = DroopCorrection(self.n, self._rad)  #: the person holds a pose where they see it
        self._enabled = np.zeros(self.n, dtype=bool)
        self.cell.set_torque(self._enabled)
        self._servo_list = list(servos.values())
        self._hand_goals = False
        self._read_registers()
        self.cell.set_goals(self._goals)
        self.publish()

    @property
    def time_s(self) -> float:
        return self.cell.time_s

    def count_to_rad(self, count: int) -> float:
        return (count - self._center) * self._rad

    def rad_to_count(self, q: float) -> int:
        return int(round(q / self._rad)) + self._center

    def step(self) -> None:
        """One millisecond: the registers into the plant (when the host changed them), the plant's step.

        The registers the host reads are written by `publish`, called before each packet is answered."""
        cell = self.cell
        changed = any(s.changed for s in self._servo_list)
        if changed:
            self._read_registers()
        if self.hand is not None:
            # a hand moves the limp joints (calibration): as strong as a servo, and it corrects what it sees
            enabled = np.ones(self.n, dtype=bool)
            hand = self._hand_eye.goal(np.array(self.hand), cell.q, cell.qd)
            cell.set_goals(np.where(self._torque_on, self._goals, hand))
            self._hand_goals = True
        else:
            enabled = self._torque_on
            if changed or self._hand_goals:
                cell.set_goals(self._goals)
                self._hand_goals = False
        if not np.array_equal(enabled, self._enabled):
            self._enabled = enabled
            cell.set_torque(enabled)
        cell.step_servos()
        if self.gripper is not None:
            on = self._gripper_on
            self.jaw.step(self._gripper_goal if on else self.jaw.angle_rad, self._gripper_cap_a if on else 0.0,
                          cell.timestep_s)
        hot = cell.temperature_c > self._max_temperature_c
        if hot.any():
            for i in np.flatnonzero(hot):
                self._overheat(self.arm_servos[i], int(cell.temperature_c[i]))

    def _read_registers(self) -> None:
        """Goals, torque enables and torque or current caps, as the host last wrote them."""
        for servo in self.servos.values():
            servo.changed = False
        arm = self.arm_servos
        self._torque_on = np.array([s.torque_on for s in arm])
        self._goals = np.array([self.count_to_rad(s.get("goal_position")) for s in arm])
        self.cell.duty_limit = np.array([self._duty_limit(s) for s in arm])
        self._max_temperature_c = np.array([s.get("max_temperature") for s in arm], dtype=float)
        if self.gripper is not None:
            self._gripper_on = self.gripper.torque_on
            self._gripper_goal = self.count_to_rad(self.gripper.get("goal_position"))
            self._gripper_cap_a = self._gripper_current_cap_a()

    def _duty_limit(self, servo: EmulatedServo) -> float:
        """The servo's drive cap as a share of full duty: an STS's torque limit (0.1 %), else none."""
        if "torque_limit" in servo.model.registers:
            return servo.get("torque_limit") / 1000.0
        return 1.0

    def _gripper_current_cap_a(self) -> float:
        """What caps the gripper's current: its goal current in current-based position mode (Dynamixel), its
        torque limit (STS), else its current limit."""
        servo, model = self.gripper, self.model
        if "torque_limit" in model.registers:
            return servo.get("torque_limit") / 1000.0 * model.stall_current_a
        cap = servo.get("current_limit")
        if servo.get("operating_mode") == CURRENT_BASED_POSITION_MODE:
            cap = min(cap, abs(servo.get("goal_current")))
        return cap * model.current_a_per_unit

    def publish(self) -> None:
        """Write what the servos measure into their registers (whole counts, the servos' units)."""
        cell, model = self.cell, self.model
        counts, qd = cell.counts, cell.qd
        duty, current, temperature = cell.duty, cell.current_a, cell.temperature_c
        feetech = model.family == "feetech"
        for i, servo in enumerate(self.arm_servos):
            servo.put("present_position", int(counts[i]) + self._center)
            servo.put("present_speed", int(round(qd[i] / model.speed_rad_s_per_unit)))
            amps = int(round(current[i] / model.current_a_per_unit))
            if feetech:
                servo.put("present_load", int(round(1000.0 * duty[i])))
            servo.put("present_current", amps if feetech else int(math.copysign(amps, duty[i])))
            servo.put("moving", int(abs(qd[i]) > 0.01))
            if not servo.faults.alarm_bits & OVERHEAT_BIT:  # an overheated servo's reading stays where it tripped
                servo.put("present_temperature", int(temperature[i]))
        if self.gripper is not None:
            jaw = self.jaw
            self.gripper.put("present_position", self.rad_to_count(jaw.angle_rad))
            self.gripper.put("present_speed", int(round(jaw.speed_rad_s / model.speed_rad_s_per_unit)))
            amps = int(round(jaw.current_a / model.current_a_per_unit))
            self.gripper.put("present_current", amps if feetech else -amps)
            if feetech:
                self.gripper.put("present_load", int(round(1000.0 * jaw.current_a / model.stall_current_a)))
            self.gripper.put("moving", int(jaw.speed_rad_s != 0.0))

    def _overheat(self, servo: EmulatedServo, celsius: int) -> None:
        """Past its limit a servo protects itself: the overheating alarm, its torque off."""
        if not servo.faults.alarm_bits & OVERHEAT_BIT:
            servo.raise_alarm(OVERHEAT_BIT)
            servo.put("present_temperature", celsius)  # the reading stays where the servo tripped
