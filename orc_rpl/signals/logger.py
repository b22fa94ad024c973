"""The signals room's logger: named getters sampled each cycle into preallocated arrays, stamped with simulated time."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from orc_rpl.errors import UsageError
from orc_rpl.signals.recording import Recording

Getter = Callable[[], Any]


class Logger:
    """`submit(name, getter)` once, `update()` every cycle, `recording()` at the end.

    Each getter returns a number or a fixed-size array; its width is taken from a first call at
    submit time. Samples go into one preallocated float array that doubles when full, so a cycle
    costs one getter call and one slice assignment per signal. A signal that is a function of another
    one's sample (`derive`) costs the cycle nothing: it is computed from the recorded samples when a
    recording is made.
    """

    def __init__(self, clock: Callable[[], float], capacity: int = 4096) -> None:
        self._clock = clock
        self._names: list[str] = []
        self._channels: dict[str, tuple[Getter, int, int]] = {}  #: the sampled signals
        self._columns: list[tuple[Getter, slice]] = []  #: the same, as update() uses them
        self._shapes: dict[str, tuple[int, ...]] = {}
        #: derived signals: name -> (source signal, function of one of its samples)
        self._derived: dict[str, tuple[str, Callable[[np.ndarray], Any]]] = {}
        self._width = 1  # column 0 is the time stamp
        self._rows = np.empty((max(16, capacity), self._width))
        self._count = 0

    def submit(self, name: str, getter: Getter) -> None:
        """Record `getter()` under `name` from the next update on; a name can be submitted once."""
        if not name or not isinstance(name, str):
            raise UsageError(f"a signal needs a non-empty name, got {name!r}")
        if name in self._shapes:
            raise UsageError(f"signal {name!r} is already submitted to this logger")
        if self._count:
            raise UsageError(f"submit signal {name!r} before the first update(): every sample has every signal")
        try:
            first = np.asarray(getter(), dtype=float)
        except Exception as exc:
            raise UsageError(f"signal {name!r}: its getter failed on a first call ({type(exc).__name__}: {exc})") from None
        if first.ndim > 1:
            raise UsageError(f"signal {name!r} must be a number or a 1-D array, got shape {first.shape}")
        width = max(1, first.size)
        start = self._width
        self._width += width
        self._channels[name] = (getter, start, self._width)
        self._columns.append((getter, slice(start, self._width)))
        self._names.append(name)
        self._shapes[name] = first.shape
        self._rows = np.empty((self._rows.shape[0], self._width))

    def derive(self, name: str, source: str, function: Callable[[np.ndarray], Any]) -> None:
        """Record `function(sample of source)` under `name`, computed when a recording is made (not every
        cycle): for a signal that is a pure function of another (the TCP of the measured joints, say)."""
        if not name or not isinstance(name, str):
            raise UsageError(f"a signal needs a non-empty name, got {name!r}")
        if name in self._shapes:
            raise UsageError(f"signal {name!r} is already submitted to this logger")
        if source not in self._shapes or source in self._derived:
            raise UsageError(f"signal {name!r} derives from {source!r}, which is not a submitted signal")
        try:
            first = np.asarray(function(np.asarray(self._channels[source][0](), dtype=float)), dtype=float)
        except Exception as exc:
            raise UsageError(f"signal {name!r}: its function failed on a first sample ({type(exc).__name__}: {exc})") from None
        if first.ndim > 1:
            raise UsageError(f"signal {name!r} must be a number or a 1-D array, got shape {first.shape}")
        self._derived[name] = (source, function)
        self._names.append(name)
        self._shapes[name] = first.shape

    @property
    def names(self) -> list[str]:
        """Submitted signal names, in submission order."""
        return list(self._names)

    def __len__(self) -> int:
        return self._count

    def update(self) -> None:
        """Take one sample of every signal, stamped with the clock's time."""
        count, rows = self._count, self._rows
        if count == len(rows):
            rows = self._rows = np.concatenate([rows, np.empty_like(rows)])
        row = rows[count]
        row[0] = self._clock()
        for getter, columns in self._columns:
            row[columns] = getter()
        self._count = count + 1

    def clear(self) -> None:
        """Drop the samples; the signals stay submitted."""
        self._count = 0

    def recording(self) -> Recording:
        """The samples so far, as a Recording (copied: the logger may go on)."""
        rows = self._rows[: self._count]
        signals = {}
        for name, (_, start, stop) in self._channels.items():
            block = rows[:, start:stop].copy()
            signals[name] = block[:, 0] if self._shapes[name] == () else block
        for name, (source, function) in self._derived.items():
            values = np.array([function(sample) for sample in signals[source]], dtype=float)
            signals[name] = values.reshape((len(rows),) + self._shapes[name])
        return Recording(rows[:, 0].copy(), {name: signals[name] for name in self._names})
