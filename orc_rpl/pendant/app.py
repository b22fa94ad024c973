"""The full-screen pendant: prompt-toolkit layout over a PendantSession, and the loop that advances the robot in time."""

from __future__ import annotations

import asyncio
import time
from typing import Any

from prompt_toolkit.application import Application
from prompt_toolkit.buffer import Buffer
from prompt_toolkit.layout import Float, FloatContainer, HSplit, Layout, VSplit, Window
from prompt_toolkit.layout.controls import BufferControl, FormattedTextControl
from prompt_toolkit.layout.dimension import Dimension
from prompt_toolkit.layout.menus import CompletionsMenu
from prompt_toolkit.layout.processors import BeforeInput
from prompt_toolkit.lexers import PygmentsLexer

from orc_rpl.pendant import views
from orc_rpl.pendant.commands import run_line
from orc_rpl.pendant.completion import RplCompleter
from orc_rpl.pendant.keys import FUNCTION_KEYS, MODES, build_key_bindings, labels
from orc_rpl.pendant.lexer import RplLexer
from orc_rpl.pendant.session import PendantSession
from orc_rpl.syntax.blocks import CLOSERS, OPENER_OF, block_keyword
from orc_rpl.syntax.printer import print_statement

#: The robot is advanced this often (wall clock) while something moves.
PUMP_PERIOD_S = 0.02
#: At most this many motion cycles per pump, so the screen stays responsive when the simulation is slow.
MAX_TICKS_PER_PUMP = 50
#: The message pane grows to this many lines for a long answer (:help, :positions, :log), then shows the last ones.
MESSAGE_LINES = 18
#: Width of the robot-state pane (characters).
STATE_WIDTH = 34


def open_blocks(text: str) -> int:
    """How many blocks the typed text opens and does not close (Enter then starts a new line instead of running)."""
    depth = 0
    for line in text.split("\n"):
        found = block_keyword(line)
        if found is None:
            continue
        word = found[0]
        depth += 1 if word in CLOSERS else -1 if word in OPENER_OF else 0
    return depth


class PendantApp:
    """The terminal pendant. The session does the work; this class turns keys into its commands and shows it."""

    def __init__(self, session: PendantSession, input: Any = None, output: Any = None, realtime: bool = True,
                 message: str = "") -> None:
        self.session = session
        self.mode = "jog"
        self.realtime = realtime
        self.message = message or "type an RPL statement to run it, or :help; F8 changes mode (jog, edit, run)"
        self.error = False
        self.editing = False                 #: Enter replaces the cursor's statement (:edit)
        self.buffer = Buffer(multiline=True, completer=RplCompleter(session), complete_while_typing=False)
        self._listing_window = Window(FormattedTextControl(self._listing), wrap_lines=False)
        body = VSplit([
            self._listing_window,
            Window(width=1, char="\u2502", style="class:gutter"),
            Window(FormattedTextControl(lambda: views.state(session)), width=STATE_WIDTH),
        ])
        prompt = BeforeInput(lambda: "edit> " if self.editing else "rpl> ", style="class:title")
        root = HSplit([
            body,
            Window(height=1, char="\u2500", style="class:gutter"),
            Window(FormattedTextControl(lambda: views.messages(self._message_tail(), self.error)),
                   height=lambda: Dimension(min=3, max=MESSAGE_LINES,
                                            preferred=min(MESSAGE_LINES, self.message.count("\n") + 1)),
                   wrap_lines=True),
            Window(BufferControl(self.buffer, lexer=PygmentsLexer(RplLexer), input_processors=[prompt]),
                   height=lambda: Dimension.exact(min(6, self.buffer.document.line_count)), wrap_lines=True),
            Window(FormattedTextControl(lambda: views.function_bar(labels(self.mode), self.mode)), height=1),
        ])
        layout = Layout(FloatContainer(root, floats=[Float(xcursor=True, ycursor=True, content=CompletionsMenu(max_height=8))]),
                        focused_element=self.buffer)
        self.application: Application[int] = Application(
            layout=layout, key_bindings=build_key_bindings(self), style=views.STYLE, full_screen=True,
            input=input, output=output, mouse_support=False)
        self._pump_task: asyncio.Task[None] | None = None

    # -- what the panes show ---------------------------------------------------------------

    def _listing(self) -> Any:
        info = self._listing_window.render_info
        height = info.window_height if info is not None else 20
        return views.listing(self.session, height)

    def _message_tail(self) -> str:
        lines = self.message.split("\n")
        return "\n".join(lines[-MESSAGE_LINES:])

    def show(self, text: str, error: bool = False) -> None:
        if text:
            self.message, self.error = text, error

    # -- actions ------------------------------------------------------------------------------

    def run_line(self, line: str) -> None:
        """A line as if typed: a `:` command or a statement; `:edit` is the terminal's own."""
        if line.strip() == ":edit":
            self.start_edit()
            return
        outcome = run_line(self.session, line)
        self.show(outcome.text or "ok", outcome.error)
        self._take_notices()
        if outcome.quit:
            self.application.exit(result=0)

    def enter(self) -> None:
        text = self.buffer.text
        if open_blocks(text) > 0:
            self.buffer.insert_text("\n    ")  # a block is being typed: go on on the next line
            return
        self.buffer.reset()
        if self.editing:
            self.editing = False
            self.run_line(":replace " + text)
            return
        self.run_line(text)

    def start_edit(self) -> None:
        try:
            stop = self.session.editor.at_cursor
        except Exception as error:  # an empty program: nothing to edit
            self.show(str(error), True)
            return
        if stop.end:
            self.show(":edit: the cursor is on an END line; move it to a statement", True)
            return
        self.editing = True
        text = print_statement(stop.statement).rstrip("\n")
        self.buffer.set_document(self.buffer.document.__class__(text, len(text)))
        self.show(f"editing line {stop.line}: Enter replaces it (it must parse), Escape cancels")

    def cancel(self) -> None:
        self.editing = False
        self.buffer.reset()

    def function_key(self, number: int) -> None:
        label, action = FUNCTION_KEYS[self.mode][number]
        session = self.session
        if action == "@mode":
            self.mode = MODES[(MODES.index(self.mode) + 1) % len(MODES)]
            self.show(f"{self.mode} mode")
        elif action == "@space":
            self.show(session.jogger.cycle_space())
        elif action == "@increment":
            self.show(session.jogger.cycle_increment())
        elif action == "@manual":
            self.run_line(":mode " + ("auto" if session.execution.mode == "manual" else "manual"))
        elif action.endswith(" "):
            self.buffer.set_document(self.buffer.document.__class__(action, len(action)))
        else:
            self.run_line(action)

    def jog_key(self, sign: int) -> None:
        try:
            self.show(self.session.jogger.jog_key(sign))
        except Exception as error:  # a refused jog is a message, never a traceback
            self.show(str(error), True)

    def _take_notices(self) -> None:
        notices = self.session.execution.notices
        if notices:
            text = "\n".join(notices)
            notices.clear()
            self.show(text)

    # -- time ---------------------------------------------------------------------------------

    async def _pump(self) -> None:
        """Advance the simulated robot with the wall clock while a job or a jog motion runs."""
        session = self.session
        last = time.perf_counter()
        while True:
            await asyncio.sleep(PUMP_PERIOD_S)
            now = time.perf_counter()
            elapsed, last = now - last, now
            if session.execution.busy or session.robot.pending() > 0:
                ticks = round(elapsed / session.robot.dt_s) if self.realtime else MAX_TICKS_PER_PUMP
                session.execution.pump(max(1, min(MAX_TICKS_PER_PUMP, ticks)))
                self._take_notices()
                self.application.invalidate()
            elif session.execution.notices:
                self._take_notices()
                self.application.invalidate()
            session.refresh_view()  # the cursor moved by keys, a jog ended: the view follows

    def _start_pump(self, application: Application[int]) -> None:
        self._pump_task = asyncio.ensure_future(self._pump())

    async def run_async(self) -> int:
        try:
            result = await self.application.run_async(pre_run=lambda: self._start_pump(self.application))
        finally:
            if self._pump_task is not None:
                self._pump_task.cancel()
        return int(result or 0)

    def run(self) -> int:
        return asyncio.run(self.run_async())
