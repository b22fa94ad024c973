"""Behaviour of the installed sensors: `INSTALL LaserSensor AS LaserDistance WITH PORT = "sim"`.

INSTALL asks the robot's sensor manager (motion.sensors.SensorManager) for a SensorPair: a simulated sensor
(PORT "sim": the cell's process model, the ragged seam) or a real one on a serial port, and its dummy twin.
`LaserSensor.On/.Off` switch the laser; `.Distance` is the seam's lateral offset from the beam (a length,
SensorFault when no seam is in view or the laser is off); `.EdgeDetected` is TRUE while the start edge of a
seam is under the beam (FALSE while the laser is off).
`INSTALL Gauge AS ForceSensor WITH PORT = "sim"` (or a serial device): `Gauge.Force` is the contact force along
the tool's z axis (simulated: the cell's contact force with a bias and noise, as a real gauge), `Gauge.Zero`
tares it.

Reads go to the sensor of the manager's environment in force (`SensorManager.current`): the installed sensor,
or its dummy while the executive precomputes a motion. `WITH DUMMY = 0mm` sets the laser dummy's answer (a seam
that far from the beam, the thesis' "middle of range"); without it the dummy sees no seam, its worst case, and
a motion that needs `.Distance` is computed only when the laser has answered.
"""

from __future__ import annotations

import dataclasses
from typing import Any

from orc_rpl.application.runtime import InstallContext, attached
from orc_rpl.errors import SensorFault
from orc_rpl.motion.force_sensor import ForceSensorDevice
from orc_rpl.motion.sensors import LaserValue, SensorManager
from orc_rpl.syntax.units import FORCE, LENGTH, Quantity


def sensor_manager(robot: Any) -> SensorManager:
    """The robot's sensors (a robot without any gets an empty manager of its own)."""
    return attached(robot, "sensors", SensorManager)


class LaserDistance:
    """An installed laser seam sensor."""

    def __init__(self, context: InstallContext) -> None:
        self.name = context.name
        port = context.attributes.get("PORT") or "sim"
        self.manager = sensor_manager(context.robot)
        self.pair = self.manager.install(context.name, "LaserDistance", str(port))
        dummy = context.attributes.get("DUMMY")
        if dummy is not None:
            if type(dummy) is not Quantity or dummy.dim != LENGTH:
                raise SensorFault(f"{self.name}: DUMMY must be a length (the seam's offset from the beam), got {dummy!r}")
            self.pair.dummy.set_dummy_value(LaserValue(True, float(dummy.value), False))

    @property
    def sensor(self) -> Any:
        """The installed laser (switched On and Off; the dummy follows its switch)."""
        return self.pair.sensor

    def value(self) -> LaserValue:
        """One sample (LaserValue) of the environment in force: the laser, or its dummy in a precomputation."""
        return self.manager.current(self.name).read()

    def On(self) -> None:  # noqa: N802 - the language's method names
        self.sensor.command("ON")

    def Off(self) -> None:  # noqa: N802
        self.sensor.command("OFF")

    def Distance(self) -> Quantity:  # noqa: N802
        if not self.sensor.on:
            raise SensorFault(f"{self.name}.Distance: the laser is off ({self.name}.On switches it on)")
        value = self.value()
        if not value.found:
            raise SensorFault(f"{self.name}.Distance: no seam in view")
        return Quantity(value.offset_m, LENGTH)

    def EdgeDetected(self) -> bool:  # noqa: N802
        return bool(self.sensor.on and self.value().edge)


class ForceSensor:
    """An installed force sensor at the flange: `.Force` the contact force along the tool's z axis, `.Zero` tares it."""

    def __init__(self, context: InstallContext) -> None:
        self.name = context.name
        port = context.attributes.get("PORT") or "sim"
        self.manager = sensor_manager(context.robot)
        self.pair = self.manager.install(context.name, ForceSensorDevice.kind, str(port))

    def Force(self) -> Quantity:  # noqa: N802 - the language's method names
        return Quantity(float(self.manager.current(self.name).read()), FORCE)

    def Zero(self) -> None:  # noqa: N802
        self.pair.sensor.command("ZERO")


def register_behaviour(registry: Any) -> None:
    """Fill the behaviour slots of LaserDistance and ForceSensor."""
    for name, factory in (("LaserDistance", LaserDistance), ("ForceSensor", ForceSensor)):
        kind = registry.install_kinds.get(name)
        if kind is not None and kind.factory is None:
            registry.install_kinds[name] = dataclasses.replace(kind, factory=factory)
