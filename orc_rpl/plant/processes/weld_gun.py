"""A spot-welding gun as a process model: closes REACTION after its close signal rises, welds, reports WELD_OK."""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

#: The TCP counts as moving when the gun closes if it is faster than this (m/s); the servo's tracking lag
#: alone leaves a few mm/s for some 30 ms after the reference has stopped.
MOVING_M_S = 0.02
#: The TCP's speed is its displacement over this window: the measured TCP may change once a motion cycle (4 ms)
#: while the plant steps every millisecond.
SPEED_WINDOW_S = 0.008


@dataclass(slots=True)
class Weld:
    """One spot as the gun saw it."""

    commanded_s: float                         #: the close signal rose
    closed_s: float                            #: the gun closed on the sheet (commanded + reaction)
    position_m: tuple[float, float, float]     #: TCP position when the gun closed (world, m)
    speed_m_s: float                           #: TCP speed when the gun closed
    done_s: float | None = None                #: WELD_OK set

    @property
    def moving(self) -> bool:
        """The robot was still moving when the gun closed (a bad weld, and a bent gun arm)."""
        return self.speed_m_s > MOVING_M_S


class WeldGunProcess:
    """Run as `CellIO.add_process`: DigOut[close] rising closes the gun after `reaction_s`, the weld takes
    `weld_time_s`, then DigIn[weld_ok] rises; the close signal falling opens the gun and clears WELD_OK.

    `tcp()` gives the TCP position (x, y, z) in m; each weld records where the gun closed and how fast the
    TCP was moving then. A weld whose gun closes while the TCP moves faster than `max_speed_m_s` is bad: the
    welder's monitoring rejects it and WELD_OK never rises. `fail=True` models a welder that never reports a
    good weld.
    """

    def __init__(self, close: int, weld_ok: int, reaction_s: float = 0.08, weld_time_s: float = 0.2,
                 tcp: Callable[[], tuple[float, float, float]] | None = None, fail: bool = False,
                 max_speed_m_s: float = MOVING_M_S) -> None:
        self.close, self.weld_ok = close, weld_ok
        self.max_speed_m_s = max_speed_m_s
        self.reaction_s, self.weld_time_s = reaction_s, weld_time_s
        self.tcp, self.fail = tcp, fail
        self.welds: list[Weld] = []
        self._commanded = False
        self._closing_at: float | None = None
        self._done_at: float | None = None
        self._last: tuple[float, tuple[float, float, float]] | None = None
        self._speed = 0.0
        self._history: deque[tuple[float, tuple[float, float, float]]] = deque()

    def __call__(self, io: Any, time_s: float) -> None:
        if self.tcp is not None:
            position = tuple(float(v) for v in self.tcp())
            self._history.append((time_s, position))  # type: ignore[arg-type]
            while len(self._history) > 2 and time_s - self._history[1][0] >= SPEED_WINDOW_S - 1e-9:
                self._history.popleft()
            first_s, first = self._history[0]
            if time_s > first_s:
                self._speed = math.dist(position, first) / (time_s - first_s)
            self._last = (time_s, position)  # type: ignore[assignment]
        command = bool(io.dig_out[self.close])
        if command and not self._commanded:
            self._closing_at = time_s + self.reaction_s
            io.dig_in[self.weld_ok] = False
        elif not command and self._commanded:
            self._closing_at = self._done_at = None
            io.dig_in[self.weld_ok] = False
        self._commanded = command
        if self._closing_at is not None and time_s >= self._closing_at - 1e-9:
            position = self._last[1] if self._last is not None else (math.nan,) * 3
            self.welds.append(Weld(self._closing_at - self.reaction_s, time_s, position, self._speed))  # type: ignore[arg-type]
            self._closing_at = None
            rejected = self.fail or self._speed > self.max_speed_m_s
            self._done_at = None if rejected else time_s + self.weld_time_s
        if self._done_at is not None and time_s >= self._done_at - 1e-9:
            io.dig_in[self.weld_ok] = True
            self.welds[-1].done_s = time_s
            self._done_at = None
