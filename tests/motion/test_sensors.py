"""The sensor framework (thesis 5.2, appendix A): kinds, pairs, real/dummy/simulated sampling, the serial laser."""

from __future__ import annotations

import math

import numpy as np
import pytest

from orc_rpl.errors import SensorFault, UsageError
from orc_rpl.motion import Actions, CartesianMotion, Params
from orc_rpl.motion.sensors import (LASER_WORST, SENSOR_KINDS, LaserDistanceSensor, LaserEmulator, LaserValue, Sensor,
                                    SensorManager, register_sensor_kind)
from orc_rpl.world.pose import Pose


class Thermometer(Sensor):
    """A test kind: real sampling counts up, the worst case is hot."""

    kind = "TestThermometer"

    def sample_real(self) -> float:
        return 20.0 + self.samples

    def dummy_value(self) -> float:
        return 100.0


register_sensor_kind(Thermometer)


def test_one_subclass_gives_real_dummy_and_simulated_behaviour() -> None:
    manager = SensorManager({"TestThermometer": lambda name: (lambda sensor: 42.0)})
    pair = manager.install("t", "TestThermometer", "sim")
    assert pair.sensor.behaviour == "simulated" and pair.dummy.behaviour == "dummy"
    assert pair.sensor.read() == 42.0 and pair.dummy.read() == 100.0
    real = manager.install("t2", "TestThermometer", "/dev/whatever")
    assert real.sensor.behaviour == "real" and real.sensor.read() == 21.0
    # no process model in the cell: a simulated sensor answers its worst case
    assert SensorManager().install("t3", "TestThermometer", "sim").sensor.read() == 100.0


def test_the_registry_refuses_a_second_kind_with_a_taken_name() -> None:
    class Other(Sensor):
        kind = "TestThermometer"

    with pytest.raises(UsageError, match="already registered"):
        register_sensor_kind(Other)
    register_sensor_kind(Thermometer)  # the same class again is harmless
    assert SENSOR_KINDS["LaserDistance"] is LaserDistanceSensor
    with pytest.raises(UsageError, match="unknown sensor kind"):
        SensorManager().install("x", "NoSuchKind")


def test_the_laser_dummy_is_its_worst_case_no_seam() -> None:
    pair = SensorManager().install("laser", "LaserDistance", "sim")
    assert pair.dummy.read() is LASER_WORST and not LASER_WORST.found and math.isnan(LASER_WORST.offset_m)


def test_a_real_laser_speaks_the_line_protocol_over_a_pty() -> None:
    answers = iter([(1.25, False), (None, True), (-0.5, False)])
    device = LaserEmulator(lambda: next(answers))
    try:
        laser = SensorManager().install("LaserSensor", "LaserDistance", device.port).sensor
        laser.command("ON")
        assert laser.on
        assert laser.read() == LaserValue(True, 0.00125, False)
        value = laser.read()
        assert not value.found and value.edge
        assert laser.read().offset_m == pytest.approx(-0.0005)
        laser.command("OFF")
        assert device.requests == ["ON", "MEAS?", "MEAS?", "MEAS?", "OFF"]
        device.lose_link()
        with pytest.raises(SensorFault, match=r"LaserSensor on /dev/.*no answer to MEAS\? within 200 ms \(link lost\?\)"):
            laser.read()
        laser.close()
    finally:
        device.close()


def test_a_laser_on_loop_url_gets_its_own_request_back_a_malformed_answer() -> None:
    laser = SensorManager().install("L", "LaserDistance", "loop://").sensor
    with pytest.raises(SensorFault, match="malformed answer 'MEAS\\?'"):
        laser.read()
    laser.close()
    with pytest.raises(SensorFault, match="the port is closed"):
        laser.read()


def test_a_missing_serial_device_is_a_sensor_fault() -> None:
    with pytest.raises(SensorFault, match="cannot open the laser on /dev/no_such_laser"):
        SensorManager().install("L", "LaserDistance", "/dev/no_such_laser")


def test_actions_see_the_sensors_and_a_path_offset_moves_the_tcp() -> None:
    from orc_rpl.motion import make_virtual_motion_layer

    layer = make_virtual_motion_layer(backend="kinematic")
    manager = SensorManager({"TestThermometer": lambda name: (lambda sensor: layer.now_s())})
    manager.install("temp", "TestThermometer", "sim")
    layer.sensors = manager
    seen: list[float] = []
    start = layer.tcp_pose()
    target = Pose.from_matrix(start)
    target = Pose(target.x, target.y + 0.1, target.z, target.a, target.b, target.c)
    offset = np.array([0.0, 0.0, 0.005])

    def during(data, slot) -> None:  # type: ignore[no-untyped-def]
        seen.append(data.sensors["temp"])
        assert data.sensors["temp"] == seen[-1]  # sampled once per cycle
        layer.set_path_offset(offset)
    handle = layer.move(CartesianMotion(target=target, kind="linear"), Params(), Actions(during=[during]))
    while not handle.done:
        layer.tick()
    assert len(seen) > 10 and seen == sorted(seen)
    end = layer.tcp_pose()
    assert end[2, 3] == pytest.approx(target.z + 0.005, abs=1e-4)
    assert end[1, 3] == pytest.approx(target.y, abs=1e-4)
