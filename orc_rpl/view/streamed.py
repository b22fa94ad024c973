"""The view of a run through shared memory: every few motion cycles the run stores a sample; the view's process does
the rest (view/stream.py, view/drawing.py). Only rare events (a planned path, a position, a weld, a new tool) are
sent as messages, from the thread where they happen."""

from __future__ import annotations

import math
import time
from functools import partial
from typing import Any

from orc_rpl.plant.posing import CellPoser, live_qpos
from orc_rpl.view.live import RATE_HZ, TRACE_EVERY_TICKS, LiveView
from orc_rpl.view.process import TRACED, process_record
from orc_rpl.view.stream import LINE, PAYLOAD, SIGNALS, TIME, TOOL, StreamWriter

#: How often (wall clock) the run looks for what changes rarely: positions taught or declared, welds made, the
#: process caption, the program's text. The robot, the trace and the caption's time and line go through the stream.
EVENTS_HZ = 10.0
_SIGNALS = tuple(TRACED)


class StreamedView(LiveView):
    """A LiveView whose per-cycle part is a few array stores into shared memory, for a scene in the view's own process
    (`remote.ViewProcess.scene`). Its robot's `tick_listeners` (CellRobot, PendantRobot) call it, so the executive
    drives the robot itself, not a wrapper."""

    def __init__(self, scene: Any, executive: Any, robot: Any, world: Any = None, rate_hz: float = RATE_HZ) -> None:
        super().__init__(scene, executive, robot, world, rate_hz)
        self.writer: StreamWriter | None = None
        self._qpos = None if self._cell is None else live_qpos(self._cell)
        self._tool_sent: Any = None
        self._tool_number = 0
        self._next_events_s = 0.0
        self._source: Any = self   # never the executive's source: the first look sends the program's lines
        self._process_caption = ""

    def attach(self, program: Any) -> None:
        poser = None if self._cell is None else CellPoser(self._cell)
        self.writer = StreamWriter(PAYLOAD + (poser.nq if poser is not None else 12))
        self.sender.always(partial(self.scene.stream_open, self.writer.name, poser, 1.0 / self.period_s))
        super().attach(program)

    def _add_cell(self) -> None:
        """Nothing to send: the view's process draws the cell from the poser the stream opened with."""

    # -- each motion cycle -------------------------------------------------------------------

    def on_tick(self) -> None:
        self._ticks += 1
        if self._ticks % TRACE_EVERY_TICKS == 0:
            self._sample()

    def _sample(self) -> None:
        """Store where the robot is (the trace's point and the latest pose), the time, the line, the process signals."""
        machine = self.executive.machine
        tool = machine.last_tool
        if tool is not self._tool_sent:  # sent before the row that needs it
            self._tool_sent, self._tool_number = tool, self._tool_number + 1
            self.sender.always(partial(self.scene.stream_tool, self._tool_number, None if tool is None else tool.matrix()))
        row = self.writer.row()  # type: ignore[union-attr]
        pointer = self.executive.pointer
        row[TIME] = self.robot.time_s()
        row[LINE] = -1 if pointer is None else pointer.line
        row[TOOL] = self._tool_number
        record = process_record(machine.robot)
        for column, name in enumerate(_SIGNALS, start=SIGNALS):
            row[column] = math.nan if record is None else record.signals.get(name, math.nan)
        if self._qpos is not None:
            row[PAYLOAD:] = self._qpos
        else:  # no simulated cell (a kinematic robot, a real arm): the flange itself
            layer = self.robot.layer
            row[PAYLOAD:] = layer.fk(layer.current_q())[:3].ravel()
        self.writer.publish()  # type: ignore[union-attr]
        if time.perf_counter() >= self._next_events_s:
            self._events()

    def _events(self) -> None:
        """What changes rarely, sent when it changed."""
        self._next_events_s = time.perf_counter() + 1.0 / EVENTS_HZ
        self._show_new_positions()
        executive = self.executive
        if executive.source is not self._source:
            self._source = executive.source
            lines = executive.source.splitlines() if executive.source is not None else []
            self.sender.always(partial(self.scene.stream_lines, lines))
        process = self.process.state(process_record(executive.machine.robot))
        if process is not None:
            if process.welds:
                self.sender.always(partial(self._show_welds, process))
            if process.caption != self._process_caption:
                self._process_caption = process.caption
                self.sender.always(partial(self.scene.stream_process, process.caption))

    def update(self) -> None:
        """Store the current state now (a pendant's jog ended, an edit, the run's start and end)."""
        self._events()
        self._sample()

    def finish(self) -> None:
        """Store the last state, wait until the view's process has drawn it, stop listening, free the stream."""
        super().finish()
        if self.writer is None:
            return
        self.update()
        self.sender.always(self._drawn)
        self.sender.always(self.scene.stream_close)
        self.writer.close()
        self.writer = None

    def _drawn(self) -> None:
        self.updates = self.scene.sync()
