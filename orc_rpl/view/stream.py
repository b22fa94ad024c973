"""The run's state for the view in shared memory: the run's process stores samples, the view's process reads them.

A ring of rows (one row per sample: simulated time, line, tool, the traced process signals, the joint positions) and
a count of the rows published. The writer fills the row the count points at, then stores the count: a few array
stores, no lock, no thread, no system call. The reader copies the rows published since its last read, then reads the
count again: a row the writer may have started to overwrite meanwhile (a reader more than a ring behind) is dropped
and counted as lost, never shown half written. It relies on the other core seeing the stores in the order they were
made, as x86-64 guarantees (total store order); the count is one aligned 64-bit store.
"""

from __future__ import annotations

from multiprocessing import resource_tracker
from multiprocessing.shared_memory import SharedMemory

import numpy as np

from orc_rpl.view.process import TRACED

#: The columns every row starts with; the sample's positions follow (MuJoCo's qpos, or a flange pose without a cell).
TIME, LINE, TOOL, SIGNALS = 0, 1, 2, 3
#: The process signals stored with each sample, in process.TRACED's order.
SIGNAL_COLUMNS = len(TRACED)
PAYLOAD = SIGNALS + SIGNAL_COLUMNS
#: Rows in the ring: a sample every 5 motion cycles of 4 ms, a `--fast` run about 30 times real time, the view reading
#: 40 times a second: some 40 rows a read, so the view may fall behind by seconds before a row is lost.
CAPACITY = 16384
_HEADER = 8  #: int64 words before the rows: the count published, the width, the capacity


class StreamWriter:
    """The run's side: `row()` is the row to fill, `publish()` makes it visible. Close it when the run is over."""

    def __init__(self, width: int, capacity: int = CAPACITY) -> None:
        self.width, self.capacity = width, capacity
        self._memory = SharedMemory(create=True, size=8 * (_HEADER + capacity * width))
        self._header = np.ndarray((_HEADER,), np.int64, self._memory.buf)
        self._header[:] = 0
        self._header[1:3] = (width, capacity)
        self._rows = np.ndarray((capacity, width), np.float64, self._memory.buf, offset=8 * _HEADER)
        self.count = 0                 #: rows published

    @property
    def name(self) -> str:
        return self._memory.name

    def row(self) -> np.ndarray:
        """The next row (a view into the ring): fill it, then publish()."""
        return self._rows[self.count % self.capacity]  # type: ignore[no-any-return]

    def publish(self) -> None:
        self.count += 1
        self._header[0] = self.count  # after the row's stores: a reader that sees the count sees the row

    def close(self) -> None:
        """Unmap and remove the block (a reader keeps its own mapping until it closes)."""
        del self._header, self._rows
        self._memory.close()
        self._memory.unlink()


class StreamReader:
    """The view's side: `take()` returns the rows published since the last call, in order, none torn."""

    def __init__(self, name: str) -> None:
        self._memory = SharedMemory(name=name)
        # the writer owns the block; without this, this process's tracker would remove it (and warn) at exit
        resource_tracker.unregister(self._memory._name, "shared_memory")  # type: ignore[attr-defined]
        self._header = np.ndarray((_HEADER,), np.int64, self._memory.buf)
        self.width, self.capacity = int(self._header[1]), int(self._header[2])
        self._rows = np.ndarray((self.capacity, self.width), np.float64, self._memory.buf, offset=8 * _HEADER)
        self.read = 0                  #: rows taken or lost so far
        self.lost = 0                  #: rows overwritten before they were read (a reader more than a ring behind)

    def take(self) -> np.ndarray:
        """(n, width) copies of the new rows, oldest first (n may be 0)."""
        end = int(self._header[0])
        start = max(self.read, end - self.capacity + 1)  # the row at end - capacity shares its slot with the next one
        slots = np.arange(start, end) % self.capacity
        rows = self._rows[slots]  # a copy (fancy indexing)
        after = int(self._header[0])
        # the writer may be filling row `after` now: a copied row sharing its slot with a row up to it is not trusted
        first_whole = min(end, max(start, after - self.capacity + 1))
        self.lost += first_whole - self.read
        self.read = end
        return rows[first_whole - start:]  # type: ignore[no-any-return]

    def close(self) -> None:
        del self._header, self._rows
        self._memory.close()
