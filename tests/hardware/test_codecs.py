"""Packet codecs and the calibration file: known packets byte for byte, damaged packets, clear errors."""

from __future__ import annotations

from pathlib import Path

import pytest

from orc_rpl.errors import UsageError
from orc_rpl.hardware.calibration import load, nominal
from orc_rpl.hardware.dynamixel import DynamixelCodec, crc16
from orc_rpl.hardware.feetech import FeetechCodec
from orc_rpl.hardware.packets import PING, READ, Instruction, Status
from orc_rpl.hardware.registers import STS3215, XM430
from orc_rpl.robot.robots import ROBOTS


def test_known_packets_are_built_byte_for_byte() -> None:
    # the manufacturers' manuals' examples: a PING to servo 1
    assert FeetechCodec().instruction(1, PING, b"") == bytes.fromhex("ffff010201fb")
    assert DynamixelCodec().instruction(1, PING, b"") == bytes.fromhex("fffffd0001030001194e")
    assert crc16(bytes.fromhex("fffffd00010300 01".replace(" ", ""))) == 0x4E19


@pytest.mark.parametrize("codec", [FeetechCodec(), DynamixelCodec()], ids=["feetech", "dynamixel"])
def test_a_status_packet_survives_noise_and_a_damaged_packet_is_reported(codec) -> None:  # noqa: ANN001
    good = codec.status(3, 0, bytes((0xFF, 0xFF, 0xFD, 0x10)))  # FF FF FD inside: stuffed on Dynamixel
    buffer = bytearray(b"\x00\x17" + good)
    packet, used, complaint = codec.parse(buffer, host=False)
    assert packet is None and complaint == "noise before a packet header"
    del buffer[:used]
    assert codec.parse(buffer, host=False) == (Status(3, 0, bytes((0xFF, 0xFF, 0xFD, 0x10))), len(good), None)
    damaged = bytearray(good[:-1] + bytes(((good[-1] + 1) & 0xFF,)))
    packet, used, complaint = codec.parse(damaged, host=False)
    assert packet is None and used == len(good) and complaint in ("checksum mismatch", "CRC mismatch")
    half = bytearray(good[: len(good) // 2])
    assert codec.parse(half, host=False) == (None, 0, None)  # wait for the rest


def test_the_host_side_parses_instructions() -> None:
    codec = DynamixelCodec()
    packet = codec.instruction(7, READ, bytes((132, 0, 4, 0)))
    assert codec.parse(bytearray(packet), host=True) == (Instruction(7, READ, bytes((132, 0, 4, 0))), len(packet), None)


def test_signed_registers_use_each_familys_encoding() -> None:
    speed = STS3215.reg("present_speed")  # sign and magnitude, bit 15
    assert speed.encode(-5) == bytes((5, 0x80)) and speed.decode(bytes((5, 0x80))) == -5
    load = STS3215.reg("present_load")  # sign bit 10
    assert load.decode((1024 + 300).to_bytes(2, "little")) == -300
    position = XM430.reg("present_position")  # two's complement
    assert position.encode(-2) == bytes((0xFE, 0xFF, 0xFF, 0xFF)) and position.decode(bytes((0xFE, 0xFF, 0xFF, 0xFF))) == -2


def test_a_calibration_file_round_trips_and_is_never_overwritten(tmp_path: Path) -> None:
    spec = ROBOTS.get("so101")
    cal = nominal(spec, "feetech")
    path = cal.save(tmp_path / "so101.json")
    assert load(path, spec) == cal
    with pytest.raises(UsageError, match="never overwritten"):
        cal.save(path)
    assert cal.to_rad(cal.to_counts([0.5, -0.25, 0.0, 1.0, -2.0])) == pytest.approx([0.5, -0.25, 0.0, 1.0, -2.0], abs=1e-3)


@pytest.mark.parametrize("text, message", [
    ("{", r"bad\.json:1:2: not a calibration file \(JSON\)"),
    ('{"format": "something else"}', "not a calibration file"),
    ('{"format": "orc_rpl servo calibration 1", "robot": "irb2400", "bus": "feetech", "joints": []}',
     "calibrates robot 'irb2400', not 'so101'"),
    ('{"format": "orc_rpl servo calibration 1", "robot": "so101", "bus": "feetech", "joints": [{}]}',
     '"joints" must list 5 joints'),
], ids=["json", "format", "robot", "joints"])
def test_a_bad_calibration_file_is_a_usage_error_naming_it(tmp_path: Path, text: str, message: str) -> None:
    path = tmp_path / "bad.json"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(UsageError, match=message):
        load(path, ROBOTS.get("so101"))
