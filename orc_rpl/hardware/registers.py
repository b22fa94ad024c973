"""The hardware room's register maps: the subset of the STS3215 and Dynamixel X-series control tables we use.

Addresses and sizes follow the manufacturers' control tables (the same ones LeRobot's motor drivers
use). Both families are little-endian; STS stores signed values as sign and magnitude (a sign bit),
Dynamixel as two's complement.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Register:
    """One register: where it is, how wide, and how a signed value is stored."""

    address: int
    size: int
    sign_bit: int | None = None     #: sign-and-magnitude sign bit (STS), or None
    twos_complement: bool = False   #: two's complement (Dynamixel)

    def decode(self, raw: bytes) -> int:
        value = int.from_bytes(raw, "little")
        if self.sign_bit is not None and value & (1 << self.sign_bit):
            return -(value & ((1 << self.sign_bit) - 1))
        if self.twos_complement and value & (1 << (8 * self.size - 1)):
            return value - (1 << (8 * self.size))
        return value

    def encode(self, value: int) -> bytes:
        if self.sign_bit is not None and value < 0:
            value = (-value) | (1 << self.sign_bit)
        return int(value & ((1 << (8 * self.size)) - 1)).to_bytes(self.size, "little")


@dataclass(frozen=True, slots=True)
class ServoModel:
    """A servo family as the drivers see it: registers, units and the block read every cycle."""

    family: str                          #: "feetech" or "dynamixel"
    name: str                            #: model name, e.g. "STS3215"
    model_number: int                    #: what PING (or a read of model_number) reports
    registers: dict[str, Register]
    counts_per_rev: int                  #: encoder counts per turn
    center_count: int                    #: the count at the middle of the range (joint zero before calibration)
    speed_rad_s_per_unit: float          #: present speed unit
    current_a_per_unit: float            #: present current unit
    voltage_v_per_unit: float            #: present voltage unit
    stall_torque_nm: float               #: torque at full load (load = 100 %), for the load-based estimate
    stall_current_a: float               #: current at full load
    state_block: tuple[int, int]         #: (address, length) of the sync read done every motion cycle
    default_return_delay_units: int      #: factory return delay (2 us units)

    def reg(self, name: str) -> Register:
        return self.registers[name]

    def rad_per_count(self) -> float:
        return 2.0 * math.pi / self.counts_per_rev

    def value(self, name: str, block: bytes) -> int:
        """A register's value out of a state block read at `state_block`."""
        reg = self.registers[name]
        offset = reg.address - self.state_block[0]
        return reg.decode(block[offset:offset + reg.size])


STS3215 = ServoModel(
    family="feetech", name="STS3215", model_number=777,
    registers={
        "model_number": Register(3, 2),
        "id": Register(5, 1),
        "baud_rate": Register(6, 1),
        "return_delay": Register(7, 1),
        "min_position": Register(9, 2),
        "max_position": Register(11, 2),
        "max_temperature": Register(13, 1),
        "homing_offset": Register(31, 2, sign_bit=11),
        "torque_enable": Register(40, 1),
        "acceleration": Register(41, 1),
        "goal_position": Register(42, 2, sign_bit=15),
        "goal_time": Register(44, 2),
        "goal_speed": Register(46, 2, sign_bit=15),
        "torque_limit": Register(48, 2),
        "lock": Register(55, 1),
        "present_position": Register(56, 2, sign_bit=15),
        "present_speed": Register(58, 2, sign_bit=15),
        "present_load": Register(60, 2, sign_bit=10),
        "present_voltage": Register(62, 1),
        "present_temperature": Register(63, 1),
        "status": Register(65, 1),
        "moving": Register(66, 1),
        "present_current": Register(69, 2, sign_bit=15),
    },
    counts_per_rev=4096, center_count=2048,
    speed_rad_s_per_unit=2.0 * math.pi / 4096,   # counts per second
    current_a_per_unit=0.0065,
    voltage_v_per_unit=0.1,
    stall_torque_nm=2.94,
    stall_current_a=2.7,
    state_block=(56, 10),                        # position, speed, load, voltage, temperature, -, status
    default_return_delay_units=250,
)

XM430 = ServoModel(
    family="dynamixel", name="XM430-W350", model_number=1020,
    registers={
        "model_number": Register(0, 2),
        "id": Register(7, 1),
        "baud_rate": Register(8, 1),
        "return_delay": Register(9, 1),
        "operating_mode": Register(11, 1),
        "homing_offset": Register(20, 4, twos_complement=True),
        "max_temperature": Register(31, 1),
        "current_limit": Register(38, 2),
        "max_position": Register(48, 4),
        "min_position": Register(52, 4),
        "torque_enable": Register(64, 1),
        "hardware_error": Register(70, 1),
        "bus_watchdog": Register(98, 1),
        "goal_current": Register(102, 2, twos_complement=True),
        "profile_acceleration": Register(108, 4),
        "profile_velocity": Register(112, 4),
        "goal_position": Register(116, 4, twos_complement=True),
        "moving": Register(122, 1),
        "present_current": Register(126, 2, twos_complement=True),
        "present_speed": Register(128, 4, twos_complement=True),
        "present_position": Register(132, 4, twos_complement=True),
        "present_voltage": Register(144, 2),
        "present_temperature": Register(146, 1),
    },
    counts_per_rev=4096, center_count=2048,
    speed_rad_s_per_unit=0.229 * 2.0 * math.pi / 60.0,   # 0.229 rpm
    current_a_per_unit=0.00269,
    voltage_v_per_unit=0.1,
    stall_torque_nm=4.1,                         # at 12 V (data sheet)
    stall_current_a=2.3,
    state_block=(126, 21),                       # current, speed, position, trajectories, voltage, temperature
    default_return_delay_units=250,
)

MODELS: dict[str, ServoModel] = {"feetech": STS3215, "dynamixel": XM430}

#: Dynamixel operating modes (register 11): position control, and current-based position control
#: (a position loop whose current is capped by goal_current: a gripper that squeezes with a set force).
POSITION_MODE = 3
CURRENT_BASED_POSITION_MODE = 5

#: Alarm bits of STS "status" (65) and of Dynamixel "hardware_error" (70): the two tables agree on these
ALARM_BITS: dict[int, str] = {1: "input voltage", 4: "overheating", 32: "overload"}


def alarm_text(bits: int) -> str:
    """The alarms set in a status / hardware-error register, in words."""
    return ", ".join(text for bit, text in ALARM_BITS.items() if bits & bit) or f"alarm {bits:#04x}"
