"""The plant room's simulated IO: digital and analog channels numbered from 1, as the language counts them."""

from __future__ import annotations

from collections.abc import Callable, Iterator

import numpy as np

from orc_rpl.errors import UsageError


class Channels:
    """A bank of IO channels, `bank[1]` .. `bank[n]`; a wrong number names the bank and its range."""

    def __init__(self, name: str, count: int, dtype: type) -> None:
        self.name = name
        self.values = np.zeros(count, dtype=dtype)  #: 0-based storage, for loggers and bulk reads

    def __len__(self) -> int:
        return self.values.size

    def _index(self, number: int) -> int:
        if isinstance(number, bool) or not isinstance(number, (int, np.integer)) or not 1 <= number <= self.values.size:
            raise UsageError(f"{self.name}[{number!r}] does not exist: {self.name} has channels 1..{self.values.size}")
        return int(number) - 1

    def __getitem__(self, number: int) -> bool | float:
        return self.values[self._index(number)].item()

    def __setitem__(self, number: int, value: bool | float) -> None:
        if self.values.dtype == np.bool_:
            if not isinstance(value, (bool, np.bool_, int)) or value not in (0, 1):
                raise UsageError(f"{self.name}[{number}] is digital: set it to TRUE/FALSE or 1/0, not {value!r}")
        elif not np.isfinite(value):
            raise UsageError(f"{self.name}[{number}] must be a finite number, not {value!r}")
        self.values[self._index(number)] = value

    def __iter__(self) -> Iterator[bool | float]:
        return iter(self.values.tolist())

    def __repr__(self) -> str:
        return f"{self.name}{self.values.tolist()}"


Process = Callable[["CellIO", float], None]


class CellIO:
    """The cell's IO: DigIn/DigOut (bool) and AnaIn/AnaOut (float, V), plus process models that link them."""

    def __init__(self, n_digital: int = 16, n_analog: int = 8) -> None:
        self.dig_in = Channels("DigIn", n_digital, np.bool_)
        self.dig_out = Channels("DigOut", n_digital, np.bool_)
        self.ana_in = Channels("AnaIn", n_analog, np.float64)
        self.ana_out = Channels("AnaOut", n_analog, np.float64)
        #: process models run after every plant step, in order (add them with add_process)
        self.processes: list[Process] = []

    def bank(self, name: str) -> Channels:
        """A bank by its language name: DigIn, DigOut, AnaIn or AnaOut."""
        banks = {c.name: c for c in (self.dig_in, self.dig_out, self.ana_in, self.ana_out)}
        try:
            return banks[name]
        except KeyError:
            raise UsageError(f"no IO bank {name!r}; the cell has {', '.join(banks)}") from None

    def add_process(self, process: Process) -> None:
        """Run `process(io, time_s)` after every plant step (a weld gun answering DigOut with DigIn, say)."""
        self.processes.append(process)

    def update(self, time_s: float) -> None:
        """Advance the process models to the plant's time (called by the cell each step)."""
        for process in self.processes:
            process(self, time_s)

    def reset(self) -> None:
        """All channels to zero/False; process models stay installed."""
        for bank in (self.dig_in, self.dig_out, self.ana_in, self.ana_out):
            bank.values[:] = 0
