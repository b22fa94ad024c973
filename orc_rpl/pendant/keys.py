"""Key bindings: F1-F8 by mode (jog, edit, run), arrows for the cursor or the jog axes, Enter, Tab, Ctrl-C."""

from __future__ import annotations

from typing import TYPE_CHECKING

from prompt_toolkit.filters import Condition
from prompt_toolkit.key_binding import KeyBindings, KeyPressEvent

from orc_rpl.pendant.completion import candidates

if TYPE_CHECKING:
    from orc_rpl.pendant.app import PendantApp

#: The pendant's modes, in the order F8 cycles through them.
MODES = ("jog", "edit", "run")

#: What F1..F8 do in each mode: a command run at once (":run"), a command put on the command line to finish
#: (a trailing space: ":teach "), or one of the pendant's own actions ("@...").
FUNCTION_KEYS: dict[str, tuple[tuple[str, str], ...]] = {
    "jog": (("help", ":help"), ("space", "@space"), ("incr", "@increment"), ("teach", ":teach "),
            ("ins.move", ":insert move"), ("modpos", ":modpos "), ("man/auto", "@manual"), ("mode", "@mode")),
    "edit": (("help", ":help"), ("select", ":select"), ("delete", ":delete"), ("up", ":shift up"),
             ("down", ":shift down"), ("edit", ":edit"), ("check", ":check"), ("mode", "@mode")),
    "run": (("help", ":help"), ("run", ":run"), ("stop", ":stop"), ("step", ":step"),
            ("back", ":back"), ("pp", ":pp"), ("exec", ":exec"), ("mode", "@mode")),
}


def labels(mode: str) -> list[str]:
    return [label for label, _ in FUNCTION_KEYS[mode]]


def build_key_bindings(app: PendantApp) -> KeyBindings:
    """The pendant's keys; everything else is prompt-toolkit's line editing."""
    kb = KeyBindings()
    empty = Condition(lambda: app.buffer.text == "")
    jogging = Condition(lambda: app.mode == "jog")
    # Enter takes a completion chosen in the menu; with none chosen it runs the line as usual
    completing = Condition(lambda: app.buffer.complete_state is not None
                           and app.buffer.complete_state.current_completion is not None)

    for number in range(8):
        @kb.add(f"f{number + 1}")
        def _function(event: KeyPressEvent, number: int = number) -> None:
            app.function_key(number)

    @kb.add("up", filter=empty & jogging)
    def _axis_up(event: KeyPressEvent) -> None:
        app.show(app.session.jogger.select_axis(-1))

    @kb.add("down", filter=empty & jogging)
    def _axis_down(event: KeyPressEvent) -> None:
        app.show(app.session.jogger.select_axis(1))

    @kb.add("left", filter=empty & jogging)
    def _jog_minus(event: KeyPressEvent) -> None:
        app.jog_key(-1)

    @kb.add("right", filter=empty & jogging)
    def _jog_plus(event: KeyPressEvent) -> None:
        app.jog_key(1)

    @kb.add("up", filter=empty & ~jogging)
    def _cursor_up(event: KeyPressEvent) -> None:
        app.session.editor.move_cursor(-1)

    @kb.add("down", filter=empty & ~jogging)
    def _cursor_down(event: KeyPressEvent) -> None:
        app.session.editor.move_cursor(1)

    @kb.add("pageup", filter=empty)
    def _page_up(event: KeyPressEvent) -> None:
        app.session.editor.move_cursor(-10)

    @kb.add("pagedown", filter=empty)
    def _page_down(event: KeyPressEvent) -> None:
        app.session.editor.move_cursor(10)

    @kb.add("enter", filter=~completing)
    def _enter(event: KeyPressEvent) -> None:
        app.enter()

    @kb.add("enter", filter=completing)
    def _take_completion(event: KeyPressEvent) -> None:
        app.buffer.complete_state = None
        app.buffer.insert_text(" ")

    @kb.add("tab")
    def _complete(event: KeyPressEvent) -> None:
        buffer = app.buffer
        if buffer.complete_state:
            buffer.complete_next()
            return
        word, words = candidates(app.session, buffer.document.current_line_before_cursor)
        if len(words) == 1:  # one way to go on: take it at once, as a shell does
            buffer.insert_text(words[0][len(word):] + " ")
        elif words:
            buffer.start_completion(select_first=False)

    @kb.add("escape", eager=True)
    def _cancel(event: KeyPressEvent) -> None:
        app.cancel()

    @kb.add("c-c")
    def _stop(event: KeyPressEvent) -> None:
        app.run_line(":stop")

    return kb
