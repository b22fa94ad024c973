"""The hardware room's host side of a servo bus: ping, read, write, sync read and sync write over pyserial."""

from __future__ import annotations

import select
import time
from typing import Any

from orc_rpl.hardware.packets import (PING, READ, SYNC_READ, SYNC_WRITE, WRITE, BusError, Codec, Status, field,
                                      read_params, sync_write_params)

#: A servo that has not answered this long after the request left is taken as absent. The wire time of
#: the exchange is added; USB adapters add their latency timer (set it to 1 ms: see docs/hardware.md),
#: and a busy host may not look at the port for a few tens of milliseconds.
REPLY_MARGIN_S = 0.050

try:  # a port that went away fails in pyserial's termios calls (POSIX) as well as in reads and writes
    import termios

    PORT_ERRORS: tuple[type[BaseException], ...] = (OSError, termios.error)
except ImportError:  # pragma: no cover - Windows
    PORT_ERRORS = (OSError,)


class ServoBus:
    """One half-duplex bus of one protocol; every call waits for (or gives up on) its replies."""

    def __init__(self, port: str, codec: Codec, baud: int = 1_000_000, reply_margin_s: float = REPLY_MARGIN_S,
                 link: Any = None) -> None:
        import serial  # pyserial

        self.port, self.codec, self.baud = port, codec, baud
        self.reply_margin_s = reply_margin_s
        if link is not None:
            self._serial = link
        else:
            try:
                self._serial = serial.serial_for_url(port, baudrate=baud, timeout=0, write_timeout=1.0)
            except (serial.SerialException, OSError, ValueError) as exc:
                raise BusError(f"cannot open the servo bus port {port!r}: {exc}") from None
        self._buffer = bytearray()
        self._dirty = False  #: an exchange failed: drain late replies before the next request
        self.bytes_on_wire = 0  #: bytes written and read so far (for the wire-time figures)

    def close(self) -> None:
        self._serial.close()

    def wire_s(self, n_bytes: int) -> float:
        """How long n bytes take on the wire: 10 bits each (start, 8 data, stop)."""
        return 10.0 * n_bytes / self.baud

    # -- the instructions -------------------------------------------------------------

    def ping(self, servo_id: int) -> int | None:
        """The servo's model number, or None when nothing answers at that id."""
        try:
            status = self._exchange(servo_id, PING, b"", 3 if self.codec.name == "dynamixel" else 0)
        except BusError:
            return None
        if self.codec.name == "dynamixel":
            return int.from_bytes(status.params[:2], "little")
        # Feetech's PING carries no data: the model number is register 3
        return int.from_bytes(self.read(servo_id, 3, 2), "little")

    def read(self, servo_id: int, address: int, length: int) -> bytes:
        """`length` bytes of a servo's registers from `address`."""
        status = self._exchange(servo_id, READ, read_params(self.codec, address, length), length)
        return status.params

    def write(self, servo_id: int, address: int, data: bytes) -> None:
        """Write registers of one servo and wait for its acknowledgement."""
        self._exchange(servo_id, WRITE, field(address, self.codec.address_bytes) + data, 0)

    def sync_write(self, address: int, length: int, data: dict[int, bytes]) -> None:
        """One packet that writes the same registers of several servos; nobody answers."""
        self._send(self.codec.instruction(self.codec.broadcast_id, SYNC_WRITE,
                                          sync_write_params(self.codec, address, length, data)))

    def sync_read(self, address: int, length: int, ids: list[int]) -> dict[int, Status]:
        """One request, one reply per servo in id order; a missing or damaged reply is a BusError naming the servo."""
        params = read_params(self.codec, address, length) + bytes(ids)
        self._send(self.codec.instruction(self.codec.broadcast_id, SYNC_READ, params))
        replies: dict[int, Status] = {}
        for servo_id in ids:
            replies[servo_id] = self._receive(servo_id, length)
        return replies

    # -- bytes ----------------------------------------------------------------------------

    def _exchange(self, servo_id: int, instruction: int, params: bytes, reply_params: int) -> Status:
        self._send(self.codec.instruction(servo_id, instruction, params))
        return self._receive(servo_id, reply_params)

    def _fail(self, servo_id: int, reason: str) -> None:
        self._dirty = True
        raise BusError(f"servo {servo_id}: {reason}", servo_id, reason)

    def _drain(self) -> None:
        """After a failed exchange, late replies may still come: wait until the wire is quiet, drop them."""
        quiet_s = self.reply_margin_s / 4
        while select.select([self._serial.fileno()], [], [], quiet_s)[0]:
            self._serial.read(self._serial.in_waiting or 1)
        self._dirty = False

    def _port_lost(self, exc: Exception) -> None:
        """The adapter itself failed (unplugged USB, a closed pseudo-terminal): a BusError for the bus as a whole."""
        self._dirty = True
        detail = getattr(exc, "strerror", None) or (exc.args[-1] if exc.args else exc)
        reason = f"the port {self.port} failed ({detail}): is the adapter unplugged?"
        raise BusError(reason, None, reason) from None

    def _send(self, packet: bytes) -> None:
        try:
            self._send_bytes(packet)
        except PORT_ERRORS as exc:  # pyserial's SerialException is an OSError too
            self._port_lost(exc)

    def _send_bytes(self, packet: bytes) -> None:
        if self._dirty:
            self._drain()
        self._buffer.clear()
        self._serial.reset_input_buffer()  # a late reply of an earlier exchange must not be taken for this one
        self._serial.write(packet)
        self.bytes_on_wire += len(packet)
        self._sent_at = time.perf_counter()
        self._sent_wire_s = self.wire_s(len(packet))

    def _receive(self, servo_id: int, n_params: int) -> Status:
        try:
            return self._receive_bytes(servo_id, n_params)
        except PORT_ERRORS as exc:
            self._port_lost(exc)
            raise  # not reached: _port_lost raises

    def _receive_bytes(self, servo_id: int, n_params: int) -> Status:
        expected = (6 if self.codec.name == "feetech" else 11) + n_params
        deadline = time.perf_counter() + self._sent_wire_s + self.wire_s(expected) + self.reply_margin_s
        codec, buffer, link = self.codec, self._buffer, self._serial
        while True:
            packet, used, complaint = codec.parse(buffer, host=False)
            if used:
                self.bytes_on_wire += used
                del buffer[:used]
            if complaint is not None:
                self._fail(servo_id, f"damaged reply on {self.port} ({complaint})")
            if isinstance(packet, Status):
                if packet.servo_id == servo_id:
                    return packet
                continue  # a late reply to an earlier request: not this servo's answer

            if used:
                continue
            remaining = deadline - time.perf_counter()
            if remaining <= 0:
                self._fail(servo_id, f"does not answer on {self.port}")
            # wait for bytes without busy polling (select on the port's descriptor), then take what came
            if not select.select([link.fileno()], [], [], remaining)[0]:
                continue
            buffer += link.read(link.in_waiting or 1)
