"""Parts to pick as a process model: closing the gripper picks up the next part, and the plant feels its mass."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any


@dataclass(slots=True)
class Pick:
    """One closing of the gripper."""

    time_s: float
    mass_kg: float              #: 0: nothing was there
    released_s: float | None = None


class PartSupply:
    """Run as `CellIO.add_process`: each rising DigOut[close] grasps the next part of `masses_kg` (0 kg: no
    part there) and puts its mass on the flange with `set_payload`; the output falling releases it."""

    def __init__(self, close: int, masses_kg: Sequence[float], set_payload: Callable[[float], None] | None) -> None:
        self.close = close
        self.masses_kg = list(masses_kg)
        self.set_payload = set_payload
        self.picks: list[Pick] = []
        self._closed = False

    def __call__(self, io: Any, time_s: float) -> None:
        closed = bool(io.dig_out[self.close])
        if closed and not self._closed:
            mass = self.masses_kg[len(self.picks)] if len(self.picks) < len(self.masses_kg) else 0.0
            self.picks.append(Pick(time_s, mass))
            if self.set_payload is not None:
                self.set_payload(mass)
        elif not closed and self._closed:
            if self.picks:
                self.picks[-1].released_s = time_s
            if self.set_payload is not None:
                self.set_payload(0.0)
        self._closed = closed
