"""Listeners: the callbacks a part runs after each of its events (a motion cycle, a plan made, a motion accepted),
added and taken away by whoever watches (the 3D view, the video, the progress display, the margins, a time limit)."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Generic, ParamSpec

P = ParamSpec("P")


class Listeners(Generic[P]):
    """Callbacks called in the order they were added. A callback listens at most once: a second `add` of it is a
    mistake that would run it twice per event, so it is refused; `discard` of one not listening does nothing (a
    watcher closed twice, or after a failed start)."""

    __slots__ = ("_callbacks",)

    def __init__(self) -> None:
        self._callbacks: tuple[Callable[P, None], ...] = ()

    def add(self, callback: Callable[P, None]) -> None:
        if callback in self._callbacks:
            raise ValueError(f"{callback!r} is already listening")
        self._callbacks = (*self._callbacks, callback)

    def discard(self, callback: Callable[P, None]) -> None:
        self._callbacks = tuple(c for c in self._callbacks if c != callback)

    @contextmanager
    def listening(self, callback: Callable[P, None]) -> Iterator[None]:
        """`with listeners.listening(callback):` it listens until the block ends, however it ends."""
        self.add(callback)
        try:
            yield
        finally:
            self.discard(callback)

    def __call__(self, *args: P.args, **kwargs: P.kwargs) -> None:
        # a tuple replaced on every change: a callback that adds or discards one while called changes the next event's
        # callbacks, never this event's
        for callback in self._callbacks:
            callback(*args, **kwargs)

    def __contains__(self, callback: object) -> bool:
        return callback in self._callbacks

    def __len__(self) -> int:
        return len(self._callbacks)

    def __iter__(self) -> Iterator[Callable[P, None]]:
        return iter(self._callbacks)
