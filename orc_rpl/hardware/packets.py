"""The hardware room's packet vocabulary: what both bus protocols share (instructions, status replies, errors)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

from orc_rpl.errors import OrcError

PING, READ, WRITE, REG_WRITE, ACTION, SYNC_READ, SYNC_WRITE = 0x01, 0x02, 0x03, 0x04, 0x05, 0x82, 0x83


class BusError(OrcError):
    """The bus itself failed: no reply, a corrupted reply, a port that cannot be opened."""

    def __init__(self, message: str, servo_id: int | None = None, reason: str = "") -> None:
        super().__init__(message)
        self.servo_id = servo_id  #: the servo that did not answer properly (None: the bus as a whole)
        self.reason = reason or message  #: what went wrong, without the servo's name


@dataclass(frozen=True, slots=True)
class Status:
    """A servo's reply: who answered, its error byte and the parameters (data read, model number...)."""

    servo_id: int
    error: int          #: the protocol's error/alarm byte (0: none)
    params: bytes


@dataclass(frozen=True, slots=True)
class Instruction:
    """A packet from the host as the emulator decodes it."""

    servo_id: int
    instruction: int
    params: bytes


class Codec(Protocol):
    """One protocol's framing: builds host packets, parses packets out of a byte stream."""

    name: str
    broadcast_id: int
    address_bytes: int  #: width of an address / length field in READ, WRITE and the SYNC packets

    def instruction(self, servo_id: int, instruction: int, params: bytes) -> bytes: ...

    def status(self, servo_id: int, error: int, params: bytes) -> bytes: ...

    def parse(self, buffer: bytearray, host: bool) -> tuple[Instruction | Status | None, int, str | None]:
        """(packet, bytes consumed, complaint): host=True parses host packets (the emulator's side).

        A complete packet gives (packet, n, None); an incomplete one (None, 0, None); a damaged one
        (None, n, why) after dropping n bytes so the caller can resynchronise.
        """
        ...

    def error_text(self, error: int) -> str: ...

    def alarm(self, error: int) -> bool:
        """True when the error byte reports a servo alarm (overload, overheating...) rather than a refused packet."""
        ...


def field(value: int, size: int) -> bytes:
    """An unsigned little-endian register value (both protocols are little-endian)."""
    return int(value & ((1 << (8 * size)) - 1)).to_bytes(size, "little")


def read_params(codec: Codec, address: int, length: int) -> bytes:
    """The parameters of a READ or the head of a SYNC READ: address and length in the protocol's width."""
    w = codec.address_bytes
    return field(address, w) + field(length, w)


def sync_write_params(codec: Codec, address: int, length: int, data: dict[int, bytes]) -> bytes:
    """The parameters of a SYNC WRITE: address, length, then each servo id followed by its data."""
    out = bytearray(read_params(codec, address, length))
    for servo_id, chunk in data.items():
        if len(chunk) != length:
            raise ValueError(f"sync write to servo {servo_id}: {len(chunk)} bytes, expected {length}")
        out.append(servo_id)
        out += chunk
    return bytes(out)
