"""bench_view's baseline: the run's view as it was before the shared-memory stream, a sending thread in the run's
process to which each motion cycle handed the robot's pose, the trace and the caption (the `_sender` and
`_in_process` figures). Not part of orc_rpl: the product's run view is orc_rpl.view.streamed.StreamedView."""

from __future__ import annotations

import threading
import time
from collections import deque
from collections.abc import Callable
from functools import partial
from typing import Any

import numpy as np

from orc_rpl.motion import scheduling
from orc_rpl.plant.shapes import Frames, cell_frames
from orc_rpl.view.live import RATE_HZ, TRACE_EVERY_TICKS, LiveView, state_caption
from orc_rpl.view.process import process_record

Job = Callable[[], None]

#: How often the sending thread looks for work. The motion cycle never wakes it: waking a thread costs the waker
#: a thread switch (measured: about 1 ms a time on a busy two-core machine), which made paced cycles late.
POLL_S = 0.005


class Sender:
    """Runs jobs on one worker thread, in order. `always(job)` jobs all run (a planned path, trace points);
    of the `latest(job)` jobs only the newest runs (the robot's pose: an older one is already stale).

    Handing over takes no lock and wakes nothing (a deque append, an attribute store): the worker polls.
    """

    def __init__(self, poll_s: float = POLL_S) -> None:
        self.poll_s = poll_s
        self._jobs: deque[Job] = deque()
        self._latest: Job | None = None
        self._latest_run: Job | None = None
        self._closed = False
        self.error: BaseException | None = None   #: the first failure of a job (the view stops; the run goes on)
        self._thread = threading.Thread(target=self._loop, name="orc-view-sender", daemon=True)
        self._thread.start()

    def always(self, job: Job) -> None:
        self._jobs.append(job)

    def latest(self, job: Job) -> None:
        self._latest = job

    def _idle(self) -> bool:
        return not self._jobs and self._latest is self._latest_run

    def drain(self) -> None:
        """Wait until every job handed over so far has run (or the view failed)."""
        while not self._idle() and self.error is None and self._thread.is_alive():
            time.sleep(self.poll_s)

    def close(self) -> None:
        """Run what is waiting, then stop the thread."""
        self.drain()
        self._closed = True
        self._thread.join()

    def _loop(self) -> None:
        while not self._closed:
            time.sleep(self.poll_s)
            scheduling.follow_paced(2)  # holding the interpreter lock, it must not be preempted while a paced cycle waits
            try:
                while self._jobs and self.error is None:
                    self._jobs.popleft()()
                    time.sleep(0)  # the motion cycle may wait for the interpreter: let it have it between jobs
                latest = self._latest  # one read: the motion cycle may store a newer one meanwhile
                if latest is not self._latest_run and self.error is None:
                    latest()
                self._latest_run = latest
            except BaseException as error:  # a closed browser connection must not stop the robot
                self.error = error
                self._jobs.clear()
                self._latest_run = self._latest


class SenderView(LiveView):
    """The run's view fed by a sending thread: each motion cycle samples the trace, and at the view's rate hands
    copies of the robot's pose, the trace, the process points and the caption's parts to the thread, which sends them
    to the scene (in the run's process, or a RemoteScene into the view's process)."""

    def __init__(self, scene: Any, executive: Any, robot: Any, world: Any = None, rate_hz: float = RATE_HZ) -> None:
        super().__init__(scene, executive, robot, world, rate_hz)
        self._next_wall_s = 0.0
        self._trace_new: list[np.ndarray] = []
        self._tool: tuple[Any, np.ndarray | None] = (None, None)
        self._lines: tuple[str | None, list[str]] = (None, [])   #: the program's source and its lines (the caption)

    def _sender(self) -> Sender:
        return Sender()

    def on_tick(self) -> None:
        self._ticks += 1
        if self._ticks % TRACE_EVERY_TICKS == 0:
            tcp = self._tcp_m()
            self._trace_new.append(tcp)
            record = process_record(self.executive.machine.robot)
            self.process.sample(None if record is None else record.signals, tcp)
        if time.perf_counter() >= self._next_wall_s:
            self.update()

    def _tcp_m(self) -> np.ndarray:
        tool = self.executive.machine.last_tool
        if tool is not self._tool[0]:
            self._tool = (tool, None if tool is None else tool.matrix())
        layer = self.robot.layer
        flange = layer.fk(layer.current_q())
        if self._tool[1] is None:
            return flange[:3, 3].copy()
        # the tool's offset applied here: the motion layer's fk with a tool checks it each call (four times the cost)
        return flange[:3, :3] @ self._tool[1][:3, 3] + flange[:3, 3]

    def update(self) -> None:
        """Hand the robot's pose, the trace, new positions and the caption to the sending thread now (copies only;
        the quaternions and the text are the sending thread's work)."""
        self._next_wall_s = time.perf_counter() + self.period_s
        frames = cell_frames(self._cell) if self._cell is not None else None
        flange = self.robot.layer.fk(self.robot.layer.current_q()) if self._tools_mounted else None
        self._show_new_positions()
        if self._trace_new:
            self.sender.always(partial(self.scene.extend_trace, self._trace_new))
            self._trace_new = []
        executive = self.executive
        process = self.process.state(process_record(executive.machine.robot))
        for name, points, colours in self.process.take_points():
            self.sender.always(partial(self.scene.extend_process, name, points, colours))
        tcp = self.robot.tcp_pose(executive.machine.last_tool)
        if self._lines[0] is not executive.source:
            self._lines = (executive.source, executive.source.splitlines() if executive.source is not None else [])
        line = executive.pointer.line if executive.pointer is not None and self._lines[1] else None
        if process is not None and process.welds:
            self.sender.always(partial(self._show_welds, process))
        self.sender.latest(partial(self._show_state, frames, flange, tcp, self.robot.time_s(), line, self._lines[1],
                                   process.caption if process is not None else ""))

    def _show_state(self, frames: Frames | None, flange: np.ndarray | None, tcp: Any, time_s: float,
                    line: int | None, lines: list[str], process: str = "") -> None:
        self.scene.show(frames, flange, state_caption(time_s, line, lines, tcp, process))
        self.updates += 1

    def finish(self) -> None:
        """Show the last state of the run, whatever the rate, and wait until it is sent; stop listening."""
        self._listening.discard(self.on_tick)
        self._trace_new.append(self._tcp_m())
        self.update()
        self.sender.close()
        super().finish()
