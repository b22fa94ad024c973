"""The hardware room's Dynamixel Protocol 2.0 framing: FF FF FD 00 ID LEN INST params CRC-16, with byte stuffing."""

from __future__ import annotations

from orc_rpl.hardware.packets import Instruction, Status

STATUS_INSTRUCTION = 0x55
HEADER = b"\xff\xff\xfd\x00"
_RESULTS = {1: "result fail", 2: "instruction error", 3: "CRC error", 4: "data range error",
            5: "data length error", 6: "data limit error", 7: "access error"}
HARDWARE_ALERT = 0x80  #: status error bit 7: read Hardware Error Status (70) for the alarm


def _crc_table() -> list[int]:
    table = []
    for i in range(256):
        crc = i << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x8005) if crc & 0x8000 else (crc << 1)
        table.append(crc & 0xFFFF)
    return table


_TABLE = _crc_table()


def crc16(data: bytes | bytearray) -> int:
    """CRC-16 of Protocol 2.0 (polynomial 0x8005, initial value 0, no reflection)."""
    crc = 0
    for byte in data:
        crc = ((crc << 8) ^ _TABLE[((crc >> 8) ^ byte) & 0xFF]) & 0xFFFF
    return crc


def stuff(params: bytes) -> bytes:
    """FF FF FD inside the parameters becomes FF FF FD FD, so no header appears inside a packet."""
    return params.replace(b"\xff\xff\xfd", b"\xff\xff\xfd\xfd")


def unstuff(params: bytes) -> bytes:
    return params.replace(b"\xff\xff\xfd\xfd", b"\xff\xff\xfd")


class DynamixelCodec:
    """Dynamixel Protocol 2.0 (X-series servos)."""

    name = "dynamixel"
    broadcast_id = 0xFE
    address_bytes = 2

    def _packet(self, servo_id: int, code: bytes, params: bytes) -> bytes:
        payload = code + stuff(params)
        head = HEADER + bytes((servo_id,)) + (len(payload) + 2).to_bytes(2, "little")
        crc = crc16(head + payload)
        return head + payload + crc.to_bytes(2, "little")

    def instruction(self, servo_id: int, instruction: int, params: bytes) -> bytes:
        return self._packet(servo_id, bytes((instruction,)), params)

    def status(self, servo_id: int, error: int, params: bytes) -> bytes:
        return self._packet(servo_id, bytes((STATUS_INSTRUCTION, error)), params)

    def parse(self, buffer: bytearray, host: bool) -> tuple[Instruction | Status | None, int, str | None]:
        start = buffer.find(HEADER)
        if start < 0:
            keep = next((k for k in (3, 2, 1) if buffer.endswith(HEADER[:k])), 0)
            drop = len(buffer) - keep
            return None, drop, ("noise before a packet header" if drop else None)
        if start > 0:
            return None, start, "noise before a packet header"
        if len(buffer) < 7:
            return None, 0, None
        length = int.from_bytes(buffer[5:7], "little")
        if length < 3:
            return None, 4, "packet length below 3"
        total = 7 + length
        if len(buffer) < total:
            return None, 0, None
        if crc16(buffer[:total - 2]) != int.from_bytes(buffer[total - 2:total], "little"):
            return None, total, "CRC mismatch"
        servo_id, code = buffer[4], buffer[7]
        if host:
            return Instruction(servo_id, code, unstuff(bytes(buffer[8:total - 2]))), total, None
        if code != STATUS_INSTRUCTION or length < 4:
            return None, total, "not a status packet"
        return Status(servo_id, buffer[8], unstuff(bytes(buffer[9:total - 2]))), total, None

    def error_text(self, error: int) -> str:
        words = []
        if error & 0x7F:
            words.append(_RESULTS.get(error & 0x7F, f"result {error & 0x7F}"))
        if error & HARDWARE_ALERT:
            words.append("hardware alert")
        return ", ".join(words) if words else "no error"

    def alarm(self, error: int) -> bool:
        return bool(error & HARDWARE_ALERT)
