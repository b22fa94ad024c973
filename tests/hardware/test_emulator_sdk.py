"""The emulator speaks the real wire protocols: the vendors' own SDKs, as independent clients, get the right answers."""

from __future__ import annotations

import time

import pytest

from tests.hardware.emulators import emulated_bus

scservo_sdk = pytest.importorskip("scservo_sdk")
dynamixel_sdk = pytest.importorskip("dynamixel_sdk")

# The SDKs give a reply 2 x LATENCY_TIMER + 2 ms (34 ms); on this shared, busy machine the emulator's
# process is sometimes not scheduled that soon. A longer wait changes nothing else.
scservo_sdk.port_handler.LATENCY_TIMER = 100
dynamixel_sdk.port_handler.LATENCY_TIMER = 100

STS3215_MODEL = 777
XM430_MODEL = 1020


def _settle(read, goals: dict[int, int], tolerance: int = 3) -> dict[int, int]:
    """Poll the positions until each is within tolerance of its goal, or 3 s pass (the emulated arm moves in real time)."""
    values = read()
    for _ in range(150):
        if all(abs(values[i] - goal) <= tolerance for i, goal in goals.items()):
            break
        time.sleep(0.02)
        values = read()
    return values


def test_feetech_sdk_pings_reads_and_sync_writes_the_emulated_so101() -> None:
    with emulated_bus("--robot", "so101", "--bus", "feetech") as path:
        port = scservo_sdk.PortHandler(path)
        assert port.openPort() and port.setBaudRate(1_000_000)
        packets = scservo_sdk.PacketHandler(0)  # 0: little-endian (STS/SMS)
        model, result, error = packets.ping(port, 1)
        assert (model, result, error) == (STS3215_MODEL, scservo_sdk.COMM_SUCCESS, 0)
        assert packets.ping(port, 12)[1] == scservo_sdk.COMM_RX_TIMEOUT  # nobody at id 12
        # the arm rests at its home pose: joint 4 at +90 deg is 1024 counts above the middle
        position, result, _ = packets.read2ByteTxRx(port, 4, 56)
        assert result == scservo_sdk.COMM_SUCCESS and position == 2048 + 1024

        writer = scservo_sdk.GroupSyncWrite(port, packets, 42, 2)
        for servo_id in range(1, 6):
            packets.write2ByteTxRx(port, servo_id, 42, packets.read2ByteTxRx(port, servo_id, 56)[0])
            packets.write1ByteTxRx(port, servo_id, 40, 1)
        goals = {1: 2148, 2: 1800, 3: 2300, 4: 3000, 5: 1948}
        for servo_id, goal in goals.items():
            assert writer.addParam(servo_id, [goal & 0xFF, goal >> 8])
        assert writer.txPacket() == scservo_sdk.COMM_SUCCESS

        reader = scservo_sdk.GroupSyncRead(port, packets, 56, 8)
        for servo_id in goals:
            reader.addParam(servo_id)

        def sync_read_all() -> dict[int, int]:
            assert reader.txRxPacket() == scservo_sdk.COMM_SUCCESS
            return {i: reader.getData(i, 56, 2) for i in goals}

        final = _settle(sync_read_all, goals)
        for servo_id, goal in goals.items():
            assert abs(final[servo_id] - goal) <= 3, f"servo {servo_id} at {final[servo_id]}, goal {goal}"
        voltage, result, _ = packets.read1ByteTxRx(port, 1, 62)
        assert result == scservo_sdk.COMM_SUCCESS and voltage == 120  # 12.0 V
        port.closePort()


def test_dynamixel_sdk_pings_reads_and_sync_writes_the_emulated_so101() -> None:
    with emulated_bus("--robot", "so101", "--bus", "dynamixel") as path:
        port = dynamixel_sdk.PortHandler(path)
        assert port.openPort() and port.setBaudRate(1_000_000)
        packets = dynamixel_sdk.PacketHandler(2.0)
        assert packets.ping(port, 3) == (XM430_MODEL, dynamixel_sdk.COMM_SUCCESS, 0)
        assert packets.ping(port, 12)[1] == dynamixel_sdk.COMM_RX_TIMEOUT
        position, result, _ = packets.read4ByteTxRx(port, 4, 132)
        assert result == dynamixel_sdk.COMM_SUCCESS and position == 2048 + 1024
        # byte stuffing: FF FF FD inside the parameters goes through and comes back intact
        assert packets.write4ByteTxRx(port, 6, 108, 0x00FDFFFF)[0] == dynamixel_sdk.COMM_SUCCESS
        assert packets.read4ByteTxRx(port, 6, 108)[0] == 0x00FDFFFF

        for servo_id in range(1, 6):
            packets.write4ByteTxRx(port, servo_id, 116, packets.read4ByteTxRx(port, servo_id, 132)[0])
            packets.write1ByteTxRx(port, servo_id, 64, 1)
        goals = {1: 2148, 2: 1800, 3: 2300, 4: 3000, 5: 1948}
        writer = dynamixel_sdk.GroupSyncWrite(port, packets, 116, 4)
        for servo_id, goal in goals.items():
            assert writer.addParam(servo_id, list(goal.to_bytes(4, "little")))
        assert writer.txPacket() == dynamixel_sdk.COMM_SUCCESS
        reader = dynamixel_sdk.GroupSyncRead(port, packets, 132, 4)
        for servo_id in goals:
            reader.addParam(servo_id)

        def sync_read_all() -> dict[int, int]:
            assert reader.txRxPacket() == dynamixel_sdk.COMM_SUCCESS
            return {i: reader.getData(i, 132, 4) for i in goals}

        final = _settle(sync_read_all, goals)
        for servo_id, goal in goals.items():
            assert abs(final[servo_id] - goal) <= 3, f"servo {servo_id} at {final[servo_id]}, goal {goal}"
        port.closePort()


def test_an_overload_alarm_shows_in_the_status_error_byte_and_the_servo_goes_limp() -> None:
    with emulated_bus("--robot", "so101", "--fault", "overload:2") as path:
        port = scservo_sdk.PortHandler(path)
        assert port.openPort() and port.setBaudRate(1_000_000)
        packets = scservo_sdk.PacketHandler(0)
        _, result, error = packets.read1ByteTxRx(port, 2, 40)
        assert result == scservo_sdk.COMM_SUCCESS and error & 32  # ERRBIT_OVERLOAD
        packets.write1ByteTxRx(port, 2, 40, 1)
        assert packets.read1ByteTxRx(port, 2, 40)[0] == 0  # torque stays off while the alarm lasts
        assert packets.read1ByteTxRx(port, 1, 40)[2] == 0  # the others are fine
        port.closePort()


def test_the_dynamixel_bus_watchdog_stops_a_servo_whose_host_falls_silent() -> None:
    with emulated_bus("--robot", "so101", "--bus", "dynamixel") as path:
        port = dynamixel_sdk.PortHandler(path)
        assert port.openPort() and port.setBaudRate(1_000_000)
        packets = dynamixel_sdk.PacketHandler(2.0)
        start = packets.read4ByteTxRx(port, 1, 132)[0]
        packets.write4ByteTxRx(port, 1, 116, start)
        packets.write1ByteTxRx(port, 1, 64, 1)
        packets.write1ByteTxRx(port, 1, 98, 5)           # 100 ms
        packets.write4ByteTxRx(port, 1, 116, start + 1500)  # a long move (about 130 deg)
        time.sleep(0.4)                                    # the host falls silent mid-move
        assert packets.read1ByteTxRx(port, 1, 98)[0] == 255  # the watchdog fired
        stopped = packets.read4ByteTxRx(port, 1, 116)[0]
        assert stopped < start + 1500                       # the goal was dropped: the servo stopped on its way
        packets.write4ByteTxRx(port, 1, 116, start)          # refused until the host clears the watchdog
        assert packets.read4ByteTxRx(port, 1, 116)[0] == stopped
        packets.write1ByteTxRx(port, 1, 98, 0)
        packets.write4ByteTxRx(port, 1, 116, start)
        assert packets.read4ByteTxRx(port, 1, 116)[0] == start
        port.closePort()
