"""The hardware room's emulated servo: a register file with the side effects a real STS / Dynamixel servo has."""

from __future__ import annotations

from dataclasses import dataclass

from orc_rpl.hardware.registers import POSITION_MODE, ServoModel


@dataclass(slots=True)
class Faults:
    """What is wrong with one emulated servo right now (set by fault injection)."""

    silent: bool = False        #: never answers (a cut wire to this servo, a dead servo)
    slow_s: float = 0.0         #: extra reply delay
    corrupt: bool = False       #: replies with a wrong checksum / CRC
    alarm_bits: int = 0         #: overload (32) or overheating (4): torque goes off, the error byte says so


class EmulatedServo:
    """One servo's control table; the emulated arm reads goals from it and writes the measured state into it."""

    def __init__(self, model: ServoModel, servo_id: int, return_delay_units: int | None = None) -> None:
        self.model = model
        self.servo_id = servo_id
        self.memory = bytearray(256)
        self.faults = Faults()
        self.put("model_number", model.model_number)
        self.put("id", servo_id)
        self.put("return_delay", model.default_return_delay_units if return_delay_units is None else return_delay_units)
        self.put("min_position", 0)
        self.put("max_position", model.counts_per_rev - 1)
        self.put("goal_position", model.center_count)
        self.put("present_position", model.center_count)
        if "torque_limit" in model.registers:
            self.put("torque_limit", 1000)
        if "current_limit" in model.registers:
            self.put("current_limit", 1193)
            self.put("goal_current", 1193)
            self.put("operating_mode", POSITION_MODE)
        self.put("present_voltage", 120)
        self.put("present_temperature", 32)
        self.put("max_temperature", 70)
        self.changed = True  #: the host wrote (or the servo changed) a register since the arm last read them

    # -- registers as values --------------------------------------------------------------

    def get(self, name: str) -> int:
        reg = self.model.registers[name]
        return reg.decode(bytes(self.memory[reg.address:reg.address + reg.size]))

    def put(self, name: str, value: int) -> None:
        reg = self.model.registers[name]
        self.memory[reg.address:reg.address + reg.size] = reg.encode(value)

    # -- the bus's view ---------------------------------------------------------------------

    def read(self, address: int, length: int) -> bytes:
        return bytes(self.memory[address:address + length])

    def write(self, address: int, data: bytes) -> None:
        """Store the bytes; torque enable while an alarm is active is refused, as the servo does."""
        goal = self.model.reg("goal_position")
        if "bus_watchdog" in self.model.registers and self.get("bus_watchdog") == 255 \
                and address <= goal.address < address + len(data):
            # a Dynamixel whose watchdog fired refuses goals until the host clears it (writes 0)
            data = data[:goal.address - address] + self.memory[goal.address:goal.address + goal.size] \
                + data[goal.address - address + goal.size:]
        self.memory[address:address + len(data)] = data
        if self.faults.alarm_bits and self.get("torque_enable"):
            self.put("torque_enable", 0)
        self.changed = True

    @property
    def torque_on(self) -> bool:
        return bool(self.get("torque_enable"))

    @property
    def return_delay_s(self) -> float:
        return 2e-6 * self.get("return_delay")

    def error_byte(self) -> int:
        """The status packet's error byte: the alarm bits (STS), or the hardware-alert bit (Dynamixel)."""
        if not self.faults.alarm_bits:
            return 0
        return self.faults.alarm_bits if self.model.family == "feetech" else 0x80

    def raise_alarm(self, bits: int) -> None:
        """The servo protects itself: alarm bits set, torque off (it goes limp, as an STS does on overload)."""
        self.faults.alarm_bits |= bits
        self.put("status" if self.model.family == "feetech" else "hardware_error", self.faults.alarm_bits)
        self.put("torque_enable", 0)
        self.changed = True
        if bits & 4:
            self.put("present_temperature", 75)
