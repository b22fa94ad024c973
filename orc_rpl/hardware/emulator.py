"""The hardware room's bus emulator: servos that answer the real wire protocol, paced as the wire would be.

A request's reply leaves when the wire would have carried it: the request's own bytes (10 bits each at
the baud rate), then for each answering servo its return delay (register "return_delay", 2 us units)
and its reply's bytes. Sync writes keep the wire busy for their bytes too.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from orc_rpl.errors import UsageError
from orc_rpl.hardware.dynamixel import DynamixelCodec
from orc_rpl.hardware.emulated_servo import EmulatedServo
from orc_rpl.hardware.feetech import FeetechCodec
from orc_rpl.hardware.packets import ACTION, PING, READ, REG_WRITE, SYNC_READ, SYNC_WRITE, WRITE, Codec, Instruction
from orc_rpl.hardware.registers import MODELS

FAULT_KINDS = ("unplugged", "silent", "slow", "corrupt", "overload", "overheat")
SLOW_REPLY_S = 0.150  #: a slow servo answers this much late: beyond the host's reply margin (50 ms)


@dataclass(frozen=True, slots=True)
class FaultPlan:
    """`KIND[:ID][@N]`: the fault starts after the N-th sync write of goal positions (0: at once)."""

    kind: str
    servo_id: int | None
    after_writes: int

    @staticmethod
    def parse(text: str) -> FaultPlan:
        head, _, after = text.partition("@")
        kind, _, ident = head.partition(":")
        if kind not in FAULT_KINDS:
            raise UsageError(f"--fault {text!r}: unknown fault {kind!r}; known: {', '.join(FAULT_KINDS)}")
        if (kind == "unplugged") != (ident == ""):
            raise UsageError(f"--fault {text!r}: " + ("unplugged takes no servo id" if ident else f"{kind} needs a servo id, e.g. {kind}:3"))
        try:
            servo_id = int(ident) if ident else None
            after_writes = int(after) if after else 0
        except ValueError:
            raise UsageError(f"--fault {text!r}: expected KIND[:ID][@WRITES] with whole numbers") from None
        return FaultPlan(kind, servo_id, after_writes)


def codec_for(bus: str) -> Codec:
    if bus == "feetech":
        return FeetechCodec()
    if bus == "dynamixel":
        return DynamixelCodec()
    raise UsageError(f"--bus must be feetech or dynamixel, not {bus!r}")


class EmulatedBus:
    """The servos on one bus and the protocol logic; `handle` returns the replies with their wire times."""

    def __init__(self, bus: str, servo_ids: list[int], baud: int = 1_000_000,
                 faults: tuple[FaultPlan, ...] = (), return_delay_units: int | None = None) -> None:
        self.codec = codec_for(bus)
        self.model = MODELS[bus]
        self.baud = baud
        self.servos = {i: EmulatedServo(self.model, i, return_delay_units) for i in servo_ids}
        self.plans = list(faults)
        for plan in self.plans:
            if plan.servo_id is not None and plan.servo_id not in self.servos:
                raise UsageError(f"--fault: no servo {plan.servo_id} on the emulated bus (ids {min(servo_ids)}..{max(servo_ids)})")
        self.unplugged = False
        self.goal_writes = 0      #: sync writes of goal positions so far (fault schedules count them)
        self.wire_free_s = 0.0    #: when the emulated wire is next idle
        self.last_packet_s = 0.0  #: when the host last sent a packet (the Dynamixel bus watchdog)
        self.bad_packets = 0
        self.torque_written = False  #: a torque enable register was written (the emulated hand watches this)
        self._arm_faults()

    def wire_s(self, n_bytes: int) -> float:
        return 10.0 * n_bytes / self.baud

    def _arm_faults(self) -> None:
        for plan in [p for p in self.plans if p.after_writes <= self.goal_writes]:
            self.plans.remove(plan)
            servo = self.servos.get(plan.servo_id) if plan.servo_id is not None else None
            if plan.kind == "unplugged":
                self.unplugged = True
            elif plan.kind == "silent":
                servo.faults.silent = True
            elif plan.kind == "slow":
                servo.faults.slow_s = SLOW_REPLY_S
            elif plan.kind == "corrupt":
                servo.faults.corrupt = True
            else:
                servo.raise_alarm(32 if plan.kind == "overload" else 4)

    # -- packets --------------------------------------------------------------------------

    def watchdog(self, now_s: float) -> None:
        """Dynamixel's bus watchdog: a servo that hears nothing for its set time stops and holds (register 98 = 255)."""
        if "bus_watchdog" not in self.model.registers:
            return
        for servo in self.servos.values():
            units = servo.get("bus_watchdog")
            if 0 < units < 255 and now_s - self.last_packet_s > 0.020 * units:
                servo.put("bus_watchdog", 255)
                servo.put("goal_position", servo.get("present_position"))
                servo.changed = True

    def handle(self, packet: Instruction, n_bytes: int, now_s: float) -> list[tuple[float, bytes]]:
        """The replies to one host packet as (time the last byte is on the wire, bytes)."""
        self.last_packet_s = now_s
        t = max(now_s, self.wire_free_s) + self.wire_s(n_bytes)
        replies: list[tuple[float, bytes]] = []
        for servo, params in self._answers(packet):
            if self.unplugged or servo.faults.silent:
                continue
            reply = self.codec.status(servo.servo_id, servo.error_byte(), params)
            if servo.faults.corrupt:
                reply = reply[:-1] + bytes(((reply[-1] + 1) & 0xFF,))
            t += servo.return_delay_s + servo.faults.slow_s + self.wire_s(len(reply))
            replies.append((t, reply))
        self.wire_free_s = t
        return replies

    def _answers(self, packet: Instruction) -> list[tuple[EmulatedServo, bytes]]:
        """Which servos answer and with what parameters; writes take effect here."""
        w = self.codec.address_bytes
        p = packet.params
        code, target = packet.instruction, packet.servo_id
        if code == SYNC_WRITE and len(p) >= 2 * w:
            address, length = int.from_bytes(p[:w], "little"), int.from_bytes(p[w:2 * w], "little")
            body = p[2 * w:]
            for k in range(0, len(body) - length, length + 1):
                servo = self.servos.get(body[k])
                if servo is not None:
                    servo.write(address, body[k + 1:k + 1 + length])
            self.torque_written |= address == self.model.reg("torque_enable").address
            if address == self.model.reg("goal_position").address:
                self.goal_writes += 1
                self._arm_faults()
            return []
        if code == SYNC_READ and len(p) >= 2 * w:
            address, length = int.from_bytes(p[:w], "little"), int.from_bytes(p[w:2 * w], "little")
            return [(self.servos[i], self.servos[i].read(address, length)) for i in p[2 * w:] if i in self.servos]
        servo = self.servos.get(target)
        if servo is None:  # the broadcast id answers nothing but PING on Dynamixel, which we do not emulate
            return []
        if code == PING:
            if self.codec.name == "dynamixel":
                return [(servo, servo.read(0, 2) + b"\x2e")]  # model number, firmware 46
            return [(servo, b"")]
        if code == READ and len(p) == 2 * w:
            address, length = int.from_bytes(p[:w], "little"), int.from_bytes(p[w:], "little")
            return [(servo, servo.read(address, length))]
        if code in (WRITE, REG_WRITE) and len(p) > w:
            servo.write(int.from_bytes(p[:w], "little"), p[w:])
            self.torque_written |= int.from_bytes(p[:w], "little") == self.model.reg("torque_enable").address
            return [(servo, b"")]
        if code == ACTION:
            return [(servo, b"")]
        return []


def hand_pose(q_min: list[float], q_max: list[float], since_s: float) -> list[float]:
    """The emulated person's hand during calibration: the middle pose, then every joint through its range."""
    if since_s < 1.5:
        return [0.5 * (lo + hi) for lo, hi in zip(q_min, q_max)]
    phase = math.sin(2.0 * math.pi * (since_s - 1.5) / 4.0)
    return [0.5 * (lo + hi) + phase * 0.49 * (hi - lo) for lo, hi in zip(q_min, q_max)]
