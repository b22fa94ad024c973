"""The pendant's event log: what happened and when (robot time), shown by :log; every part of the session writes to it."""

from __future__ import annotations

from collections.abc import Callable


class EventLog:
    """Events as `     1.234s  text` lines, stamped with the controller clock."""

    def __init__(self, clock_s: Callable[[], float]) -> None:
        self.lines: list[str] = []
        self._clock_s = clock_s

    def record(self, text: str) -> str:
        """Log an event and return it, so a command can answer with the same text."""
        self.lines.append(f"{self._clock_s():9.3f}s  {text}")
        return text
