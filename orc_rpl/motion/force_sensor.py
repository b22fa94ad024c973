"""The force sensor at the flange (thesis 5.2): the contact force along the tool's z axis, real over a serial line or simulated.

A real ForceSensor speaks the line protocol of `SerialLineSensor` (115200 8N1, ASCII lines ending in `\\n`):

    ZERO  -> OK               take the present force as zero (tare)
    F?    -> F <newtons>      the force along the tool's z axis, pushing on the part positive
    any   -> ERR <text>       the device's error

Its dummy twin answers the sensor's range (the worst case a motion precomputed before the real sensor has
answered must allow for). A simulated one reads the cell's contact force (`simulate(sensor)`) and, as a real
gauge does, adds a bias and white noise (seeded per sensor name, so runs repeat).
"""

from __future__ import annotations

import math
import zlib
from collections.abc import Callable
from typing import Any

import numpy as np

from orc_rpl.errors import SensorFault
from orc_rpl.motion.sensors import LaserEmulator, SerialLineSensor, register_sensor_kind

#: The range of the sensor (N): its dummy value.
RANGE_N = 500.0
#: A simulated gauge's bias (N) and noise (N, standard deviation of each reading).
SIM_BIAS_N = 0.5
SIM_NOISE_N = 0.2


class ForceSensorDevice(SerialLineSensor):
    """A force sensor at the flange; `read()` gives newtons (float)."""

    kind = "ForceSensor"
    what = "the force sensor"

    tare_n = 0.0               #: a simulated sensor's zero (a real one keeps its own)

    def dummy_value(self) -> float:
        return RANGE_N

    def command(self, command: str) -> None:
        """ZERO: take the present force as zero (the real device, or a simulated sensor's tare)."""
        if command != "ZERO":
            super().command(command)
        elif self.behaviour == "real":
            self.command_real(command)
        elif self.behaviour == "simulated":
            self.tare_n += float(self.read())

    def command_real(self, command: str) -> None:
        if command == "ZERO":
            answer = self._ask("ZERO")
            if answer != "OK":
                raise SensorFault(f"{self.name} on {self.port}: ZERO answered {answer!r}, expected OK")

    def sample_real(self) -> float:
        answer = self._ask("F?")
        parts = answer.split()
        if len(parts) == 2 and parts[0] == "F":
            try:
                value = float(parts[1])
            except ValueError:
                value = math.nan
            if math.isfinite(value):
                return value
        raise SensorFault(f"{self.name} on {self.port}: malformed answer {answer!r} to F?")


register_sensor_kind(ForceSensorDevice)


def simulated_gauge(name: str, contact_force_n: Callable[[], float], bias_n: float = SIM_BIAS_N,
                    noise_n: float = SIM_NOISE_N) -> Callable[[Any], float]:
    """The simulated sampling of a ForceSensor: the cell's contact force plus a bias and seeded noise; ZERO
    (the sensor's `tare_n`, set by the application) is taken off as on a real gauge."""
    rng = np.random.default_rng(zlib.crc32(name.encode()))

    def sample(sensor: Any) -> float:
        return contact_force_n() + bias_n + float(rng.normal(0.0, noise_n)) - getattr(sensor, "tare_n", 0.0)
    return sample


class ForceEmulator(LaserEmulator):
    """A ForceSensor device for tests: answers ZERO and F? on the master side of a pty; `measure()` gives newtons."""

    def __init__(self, measure: Callable[[], float] = lambda: 0.0) -> None:
        self.tare_n = 0.0
        super().__init__(measure)

    def answer(self, request: str) -> str:
        if request == "ZERO":
            self.tare_n = float(self.measure())
            return "OK"
        if request == "F?":
            return f"F {float(self.measure()) - self.tare_n:.3f}"
        return f"ERR unknown command {request}"
