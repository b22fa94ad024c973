"""The plant room's servo gripper: a jaw on a bus servo whose current is capped, closing on an object or on nothing."""

from __future__ import annotations

from dataclasses import dataclass

#: The jaw's travel (rad at the servo): the SO-101's moving jaw, from slightly past closed to wide open.
JAW_RANGE_RAD = (-0.1745, 1.7453)
#: How far an object gives under the jaw's torque (N m/rad at the servo): a firm plastic part.
OBJECT_STIFFNESS_NM_RAD = 20.0
#: Torque the jaw's own gears and linkage take while moving freely (N m at the servo).
JAW_FRICTION_NM = 0.05


@dataclass(frozen=True, slots=True)
class GripperServo:
    """The servo that drives the jaw: its position loop and motor (as in robot.servo_plants)."""

    stall_torque_nm: float
    stall_current_a: float
    no_load_speed_rad_s: float
    rad_per_count: float
    position_gain_duty_per_count: float = 1.0 / 16.0


class ServoGripper:
    """One jaw: the servo's position loop moves it at up to the motor's speed for the load; an object in the way
    stops it, and the servo squeezes with what its current cap allows (Dynamixel's current-based position mode,
    an STS's torque limit). `object_rad`: where an object meets the closing jaw (None: nothing to grip)."""

    def __init__(self, servo: GripperServo, angle_rad: float = 0.0, object_rad: float | None = None) -> None:
        self.servo = servo
        self.angle_rad = angle_rad
        self.speed_rad_s = 0.0
        self.current_a = 0.0
        self.object_rad = object_rad

    def step(self, goal_rad: float, current_cap_a: float, dt_s: float) -> None:
        """One step of the servo's loop toward goal_rad with its current capped at current_cap_a."""
        s = self.servo
        goal = min(max(goal_rad, JAW_RANGE_RAD[0]), JAW_RANGE_RAD[1])
        cap_nm = max(0.0, current_cap_a) * s.stall_torque_nm / s.stall_current_a
        error_counts = (goal - self.angle_rad) / s.rad_per_count
        demand_nm = min(abs(error_counts) * s.position_gain_duty_per_count, 1.0) * s.stall_torque_nm
        torque_nm = min(demand_nm, cap_nm)
        on_object = self.object_rad is not None and self.angle_rad <= self.object_rad and goal < self.object_rad
        if on_object:
            # squeezing: the object gives by torque / stiffness; the jaw stands still there
            self.speed_rad_s = 0.0
            self.angle_rad = self.object_rad - torque_nm / OBJECT_STIFFNESS_NM_RAD
            self.current_a = torque_nm * s.stall_current_a / s.stall_torque_nm
            return
        drive_nm = max(0.0, torque_nm - JAW_FRICTION_NM)
        speed = s.no_load_speed_rad_s * drive_nm / s.stall_torque_nm  # the motor's speed-torque line
        step = min(speed * dt_s, abs(goal - self.angle_rad))
        moved = step if goal > self.angle_rad else -step
        if self.object_rad is not None and self.angle_rad > self.object_rad >= self.angle_rad + moved:
            moved = self.object_rad - self.angle_rad  # it meets the object within this step
        self.angle_rad += moved
        self.speed_rad_s = moved / dt_s
        self.current_a = (min(torque_nm, JAW_FRICTION_NM) if moved else 0.0) * s.stall_current_a / s.stall_torque_nm
