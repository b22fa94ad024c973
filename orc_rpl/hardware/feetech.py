"""The hardware room's Feetech STS/SMS framing (little-endian): FF FF ID LEN INST params CHECKSUM."""

from __future__ import annotations

from orc_rpl.hardware.packets import Instruction, Status

_ERRORS = ((1, "input voltage"), (2, "angle sensor"), (4, "overheating"), (8, "overcurrent"), (32, "overload"))
#: error bits that are alarms of the servo (it protects itself), not complaints about a packet
_ALARMS = 1 | 2 | 4 | 8 | 32


def checksum(body: bytes | bytearray) -> int:
    """~(ID + LEN + INST/ERR + params) & 0xFF."""
    return ~sum(body) & 0xFF


class FeetechCodec:
    """Feetech STS/SMS protocol (the SO-100/SO-101 STS3215 servos); SCS servos are big-endian and not covered."""

    name = "feetech"
    broadcast_id = 0xFE
    address_bytes = 1

    def _packet(self, servo_id: int, code: int, params: bytes) -> bytes:
        body = bytes((servo_id, len(params) + 2, code)) + params
        return b"\xff\xff" + body + bytes((checksum(body),))

    def instruction(self, servo_id: int, instruction: int, params: bytes) -> bytes:
        return self._packet(servo_id, instruction, params)

    def status(self, servo_id: int, error: int, params: bytes) -> bytes:
        return self._packet(servo_id, error, params)

    def parse(self, buffer: bytearray, host: bool) -> tuple[Instruction | Status | None, int, str | None]:
        start = buffer.find(b"\xff\xff")
        if start < 0:
            # keep a trailing FF: it may be the first half of the next header
            drop = len(buffer) - (1 if buffer.endswith(b"\xff") else 0)
            return None, drop, ("noise before a packet header" if drop else None)
        if start > 0:
            return None, start, "noise before a packet header"
        # FF FF FF ID...: a third FF is part of the header run, not an id
        if len(buffer) >= 3 and buffer[2] == 0xFF:
            return None, 1, None
        if len(buffer) < 4:
            return None, 0, None
        length = buffer[3]
        if length < 2:
            return None, 2, "packet length below 2"
        total = 4 + length
        if len(buffer) < total:
            return None, 0, None
        body = bytes(buffer[2:total - 1])
        if checksum(body) != buffer[total - 1]:
            return None, total, "checksum mismatch"
        servo_id, code, params = body[0], body[2], body[3:]
        packet = Instruction(servo_id, code, params) if host else Status(servo_id, code, params)
        return packet, total, None

    def error_text(self, error: int) -> str:
        words = [text for bit, text in _ERRORS if error & bit]
        return ", ".join(words) if words else f"error byte {error:#04x}"

    def alarm(self, error: int) -> bool:
        return bool(error & _ALARMS)
