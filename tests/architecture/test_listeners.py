"""Listeners: who watches a run is called once per event, in order, and leaves nothing behind."""

from __future__ import annotations

import pytest

from orc_rpl.listeners import Listeners


def test_callbacks_run_in_order_once_each_and_a_second_add_is_refused() -> None:
    heard: list[tuple[str, int]] = []
    listeners: Listeners[[int]] = Listeners()
    first, second = (lambda n: heard.append(("first", n))), (lambda n: heard.append(("second", n)))
    listeners.add(first)
    listeners.add(second)
    with pytest.raises(ValueError, match="already listening"):
        listeners.add(first)
    listeners(7)
    assert heard == [("first", 7), ("second", 7)] and len(listeners) == 2 and first in listeners


def test_a_callback_that_leaves_while_called_changes_the_next_event_not_this_one() -> None:
    heard: list[str] = []
    listeners: Listeners[[]] = Listeners()

    def leaving() -> None:
        heard.append("leaving")
        listeners.discard(leaving)

    listeners.add(leaving)
    listeners.add(lambda: heard.append("staying"))
    listeners()
    listeners()
    assert heard == ["leaving", "staying", "staying"]


def test_listening_ends_with_its_block_even_on_an_error_and_a_second_discard_does_nothing() -> None:
    listeners: Listeners[[]] = Listeners()
    callback = lambda: None  # noqa: E731
    with pytest.raises(RuntimeError), listeners.listening(callback):
        assert callback in listeners
        raise RuntimeError("the run failed")
    assert len(listeners) == 0
    listeners.discard(callback)
    assert list(listeners) == []
