"""Sensors of the motion layer (thesis 5.2 and appendix A): one class per kind, real, dummy and simulated sampling.

A sensor kind is one subclass of `Sensor` that defines real sampling (`sample_real`, e.g. over pyserial) and its
worst-case `dummy_value` (used when a motion is precomputed before the sensor can be read). Every installed
sensor gets both behaviours through the `SensorManager`, which makes a `SensorPair` (thesis: `SensorPair`,
`MotionSensors`): the sensor itself, real or simulated, and a dummy of the same kind. Simulated sampling is a
function given by the cell (a process model such as the ragged seam); without one a simulated sensor answers
its dummy value. Kinds are registered by name (`register_sensor_kind`); a second kind with a taken name is
refused.

Actions see the installed sensors through `MotionData.sensors`: a mapping name -> value sampled at most once
per motion cycle, and only when an action reads it (so a cycle without sensor actions costs nothing).

The manager has two sensor environments (thesis appendix A: one structure of all real sensors, one of all dummies):
`current(name)` is the installed sensor, or its dummy while `dummies()` holds. The executive precomputes the next
motion inside `dummies()`, so a target that reads a sensor is computed from the dummy's value, before the real
sensor has been asked (and with no exchange on its port). A dummy answers `dummy_value()`, or the value the
application set for it (`set_dummy_value`, the thesis' SetDummyVal: `INSTALL ... WITH DUMMY = ...`).

The LaserDistance line protocol (a real sensor on a serial port, 115200 8N1, ASCII lines ending in "\\n"):

    host -> sensor      sensor -> host
    ON                  OK                      laser on
    OFF                 OK                      laser off
    MEAS?               D <offset_mm> <edge>    lateral offset of the seam from the beam (mm, signed),
                                                edge 1 while the start edge of a seam is under the beam
                        D NONE 0                no seam in view
                        ERR <text>              the sensor's own fault

An answer that does not come within `timeout_s` (default 0.2 s), a closed port or a malformed answer is a
`SensorFault` naming the sensor and its port.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any, ClassVar

from orc_rpl.errors import SensorFault, UsageError
from orc_rpl.motion.ports import LOOPBACK, device_problem, is_device, port_problem

__all__ = ["SENSOR_KINDS", "LaserDistanceSensor", "LaserValue", "Sensor", "SensorFault", "SensorManager", "SensorPair",
           "SerialLineSensor",
           "SensorReadings", "register_sensor_kind"]

#: Sensor kinds by name (`SensorDefs` in the thesis); `register_sensor_kind` adds one and refuses duplicates.
SENSOR_KINDS: dict[str, type[Sensor]] = {}

#: A simulated sampling function given by the cell: called with the sensor, returns its value.
SimFunction = Callable[["Sensor"], Any]


def register_sensor_kind(cls: type[Sensor], name: str | None = None) -> type[Sensor]:
    """Register a sensor kind under `name` (default: its `kind`); a name already taken is a UsageError."""
    name = name or cls.kind
    if not name:
        raise UsageError(f"sensor class {cls.__name__} has no kind name")
    if name in SENSOR_KINDS and SENSOR_KINDS[name] is not cls:
        raise UsageError(f"a sensor kind named {name!r} is already registered ({SENSOR_KINDS[name].__name__})")
    SENSOR_KINDS[name] = cls
    return cls


class Sensor:
    """One sensor; its behaviour ("real", "dummy" or "simulated") is fixed when the manager makes it.

    A subclass sets `kind`, implements `sample_real()` and `dummy_value()`, and may override `open`/`close`
    and `set_laser`-style commands through `command(name)`. `read()` is the generic sampling (`GetVal`).
    """

    kind: ClassVar[str] = ""

    def __init__(self, name: str, behaviour: str, port: str | None = None, simulate: SimFunction | None = None,
                 **options: Any) -> None:
        if behaviour not in ("real", "dummy", "simulated"):
            raise UsageError(f"sensor behaviour must be real, dummy or simulated, not {behaviour!r}")
        self.name, self.behaviour, self.port, self.simulate = name, behaviour, port, simulate
        self.options = options
        self.on = False
        self.samples = 0
        self._dummy: Any = None        #: the value set by the application (set_dummy_value), None: dummy_value()

    # -- what a kind defines ---------------------------------------------------------------

    def sample_real(self) -> Any:
        """Sample the real device (only called for behaviour "real")."""
        raise NotImplementedError

    def dummy_value(self) -> Any:
        """The worst-case value, for precomputation."""
        raise NotImplementedError

    def command_real(self, command: str) -> None:
        """Send a command ("ON", "OFF") to the real device."""

    # -- generic ---------------------------------------------------------------------------

    def set_dummy_value(self, value: Any) -> None:
        """What dummy sampling answers from now on (`SetDummyVal`); None: the kind's `dummy_value()` again."""
        self._dummy = value

    def dummy_sample(self) -> Any:
        """Dummy sampling: the value the application set, else the kind's worst case."""
        return self.dummy_value() if self._dummy is None else self._dummy

    def read(self) -> Any:
        """Sample according to the behaviour (`GetVal`)."""
        self.samples += 1
        if self.behaviour == "real":
            return self.sample_real()
        if self.behaviour == "simulated" and self.simulate is not None:
            return self.simulate(self)
        return self.dummy_sample()

    def command(self, command: str) -> None:
        """Switch the sensor ("ON", "OFF"); a real one is told over its link."""
        if self.behaviour == "real":
            self.command_real(command)
        self.on = command == "ON"

    def close(self) -> None:
        """Release the device (a real sensor's port)."""

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.name!r}, {self.behaviour})"


@dataclass(frozen=True, slots=True)
class SensorPair:
    """The installed sensor (real or simulated) and its dummy twin of the same kind (thesis appendix A)."""

    sensor: Sensor
    dummy: Sensor


class SensorReadings(Mapping[str, Any]):
    """`MotionData.sensors`: name -> value, each sensor sampled at most once per motion cycle, on first access."""

    def __init__(self, manager: SensorManager) -> None:
        self._manager = manager
        self._cycle = -1
        self._cache: dict[str, Any] = {}

    def new_cycle(self, cycle: int) -> SensorReadings:
        if cycle != self._cycle:
            self._cycle, self._cache = cycle, {}
        return self

    def __getitem__(self, name: str) -> Any:
        if name not in self._cache:
            self._cache[name] = self._manager.pairs[name].sensor.read()
        return self._cache[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._manager.pairs)

    def __len__(self) -> int:
        return len(self._manager.pairs)


class SensorManager:
    """The installed sensors (`MotionSensors`): makes a SensorPair per sensor and reads them for actions.

    `simulations` maps a kind name to a factory `(sensor_name) -> SimFunction` given by the cell; a sensor
    installed with PORT "sim" is simulated with it (or answers its dummy value when the cell has none).
    """

    def __init__(self, simulations: dict[str, Callable[[str], SimFunction | None]] | None = None,
                 allow_devices: bool = True) -> None:
        self.pairs: dict[str, SensorPair] = {}
        #: False on a simulated run unless its command line allows real devices (`orc run --allow-devices`)
        self.allow_devices = allow_devices
        self.simulations = dict(simulations or {})
        self.readings = SensorReadings(self)
        self.environment = "real"      #: "dummy" while `dummies()` holds: `current()` gives the dummies

    @contextmanager
    def dummies(self) -> Iterator[None]:
        """The dummy environment for a precomputation: `current(name)` is each sensor's dummy meanwhile."""
        previous, self.environment = self.environment, "dummy"
        try:
            yield
        finally:
            self.environment = previous

    def current(self, name: str) -> Sensor:
        """The sensor of the environment in force: the installed one, or its dummy inside `dummies()`."""
        pair = self.pairs[name]
        return pair.dummy if self.environment == "dummy" else pair.sensor

    def dummy_reads(self) -> int:
        """How many times the dummies have been sampled (a precomputation that read none did not need them)."""
        return sum(pair.dummy.samples for pair in self.pairs.values())

    def install(self, name: str, kind: str, port: str = "sim", **options: Any) -> SensorPair:
        """Make the pair for a sensor of `kind` named `name`: simulated for PORT "sim", else real on `port`."""
        cls = SENSOR_KINDS.get(kind)
        if cls is None:
            raise UsageError(f"unknown sensor kind {kind!r}; known: {', '.join(sorted(SENSOR_KINDS))}")
        old = self.pairs.pop(name, None)
        if old is not None:
            old.sensor.close()
        problem = port_problem(port)
        if problem is not None:
            raise SensorFault(f"{name}: {problem}")
        if is_device(port) and not self.allow_devices:
            raise SensorFault(f"{name}: this run opens no real device, and PORT names {port} "
                              "(the command line allows devices with --allow-devices)")
        if port == "sim":
            factory = self.simulations.get(kind)
            sensor = cls(name, "simulated", None, factory(name) if factory is not None else None, **options)
        else:
            sensor = cls(name, "real", port, **options)
        pair = SensorPair(sensor, cls(name, "dummy"))
        self.pairs[name] = pair
        return pair

    def sensor(self, name: str) -> Sensor:
        return self.pairs[name].sensor

    def dummy(self, name: str) -> Sensor:
        return self.pairs[name].dummy

    def close(self) -> None:
        for pair in self.pairs.values():
            pair.sensor.close()


# -- the laser distance sensor ---------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class LaserValue:
    """One laser sample: the seam's lateral offset from the beam (m, signed) and whether an edge is under it."""

    found: bool                 #: a seam is in view
    offset_m: float             #: lateral offset of the seam from the beam, m (nan when not found)
    edge: bool = False          #: the start edge of a seam is under the beam


#: The laser's worst case for precomputation: no seam in view.
LASER_WORST = LaserValue(False, math.nan, False)


class SerialLineSensor(Sensor):
    """A real sensor that speaks an ASCII line protocol over pyserial (115200 8N1, lines ending in `\\n`):
    one request, one answer line within `timeout_s`; `ERR <text>` is the device's error."""

    BAUD = 115200
    what = "sensor"            #: how messages name the device ("the laser")

    def __init__(self, name: str, behaviour: str, port: str | None = None, simulate: SimFunction | None = None,
                 timeout_s: float = 0.2, link: Any = None, **options: Any) -> None:
        super().__init__(name, behaviour, port, simulate, **options)
        self.timeout_s = timeout_s
        self._link = link
        if behaviour == "real" and link is None:
            import serial

            problem = port_problem(port or "") or device_problem(port or "")
            if problem is not None:  # never a URL scheme that reaches files or the network
                raise SensorFault(f"{name}: {problem}")
            try:
                if port == LOOPBACK:
                    self._link = serial.serial_for_url(port, baudrate=self.BAUD, timeout=timeout_s)
                else:
                    self._link = serial.Serial(port, baudrate=self.BAUD, timeout=timeout_s)
            except (serial.SerialException, ValueError, OSError) as error:
                raise SensorFault(f"{name}: cannot open {self.what} on {port}: {error}") from None

    def _ask(self, request: str) -> str:
        import serial

        link = self._link
        if link is None:
            raise SensorFault(f"{self.name} on {self.port}: the port is closed")
        try:
            link.reset_input_buffer()
            link.write((request + "\n").encode("ascii"))
            line = link.readline()
        except (serial.SerialException, OSError, ValueError) as error:
            raise SensorFault(f"{self.name} on {self.port}: link lost ({error})") from None
        if not line.endswith(b"\n"):
            raise SensorFault(f"{self.name} on {self.port}: no answer to {request} within "
                              f"{1000 * self.timeout_s:.0f} ms (link lost?)")
        text = line.decode("ascii", "replace").strip()
        if text.startswith("ERR"):
            raise SensorFault(f"{self.name} on {self.port}: the sensor reports {text[3:].strip() or 'an error'}")
        return text

    def close(self) -> None:
        if self._link is not None:
            try:
                self._link.close()
            finally:
                self._link = None


class LaserDistanceSensor(SerialLineSensor):
    """A laser seam sensor: real over pyserial with the line protocol of this module's docstring."""

    kind = "LaserDistance"
    what = "the laser"

    def dummy_value(self) -> LaserValue:
        return LASER_WORST

    def command_real(self, command: str) -> None:
        answer = self._ask(command)
        if answer != "OK":
            raise SensorFault(f"{self.name} on {self.port}: {command} answered {answer!r}, expected OK")

    def sample_real(self) -> LaserValue:
        answer = self._ask("MEAS?")
        parts = answer.split()
        try:
            if len(parts) == 3 and parts[0] == "D":
                edge = parts[2] == "1"
                if parts[1] == "NONE":
                    return LaserValue(False, math.nan, edge)
                return LaserValue(True, float(parts[1]) / 1000.0, edge)
        except ValueError:
            pass
        raise SensorFault(f"{self.name} on {self.port}: malformed answer {answer!r} to MEAS?")


register_sensor_kind(LaserDistanceSensor)


class LaserEmulator:
    """A LaserDistance device for tests and demos: answers the line protocol on the master side of a pty.

    `measure()` gives the (offset_mm or None, edge) it reports; `lose_link()` makes it stop answering.
    """

    def __init__(self, measure: Callable[[], Any] = lambda: (0.0, False)) -> None:
        import os
        import threading

        self.measure = measure
        self.master, self._slave = os.openpty()
        import tty

        tty.setraw(self._slave)
        self.port = os.ttyname(self._slave)
        self.requests: list[str] = []
        self.answering = True
        self._stop = False
        self._thread = threading.Thread(target=self._serve, daemon=True)
        self._thread.start()

    def _serve(self) -> None:
        import os
        import select

        buffer = b""
        while not self._stop:
            ready, _, _ = select.select([self.master], [], [], 0.05)
            if not ready:
                continue
            try:
                chunk = os.read(self.master, 256)
            except OSError:
                return
            buffer += chunk
            while b"\n" in buffer:
                line, buffer = buffer.split(b"\n", 1)
                request = line.decode("ascii", "replace").strip()
                self.requests.append(request)
                if not self.answering:
                    continue
                os.write(self.master, (self.answer(request) + "\n").encode("ascii"))

    def answer(self, request: str) -> str:
        """The device's answer line to one request (a subclass emulates another device)."""
        if request in ("ON", "OFF"):
            return "OK"
        if request == "MEAS?":
            offset, edge = self.measure()
            return f"D {'NONE' if offset is None else f'{offset:.3f}'} {int(edge)}"
        return f"ERR unknown command {request}"

    def lose_link(self) -> None:
        """The device stops answering (a cut cable)."""
        self.answering = False

    def close(self) -> None:
        import os

        self._stop = True
        self._thread.join(timeout=1.0)
        for fd in (self.master, self._slave):
            try:
                os.close(fd)
            except OSError:
                pass
