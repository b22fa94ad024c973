"""In the view's process: reads the run's samples from shared memory and draws them (the robot, the trace, the caption).

Everything the run's process used to do for each update happens here: the forward kinematics of the geoms, the
flange and the TCP from the stored joint positions, the quaternions, the caption's text, the scene's messages.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from orc_rpl.view.live import RATE_HZ, state_caption
from orc_rpl.view.process import TRACED, ProcessOverlay
from orc_rpl.view.stream import LINE, PAYLOAD, SIGNALS, TIME, TOOL, StreamReader
from orc_rpl.world.pose import Pose


class StreamDrawer:
    """Draws the rows of one run's stream into a CellScene. `poser` (plant.posing.CellPoser) draws the cell where it
    stood when the stream opened and places it at a row's joint positions; without one (no simulated cell) a row
    carries the flange pose itself (3x4, row-major)."""

    def __init__(self, scene: Any, name: str, poser: Any = None, rate_hz: float = RATE_HZ) -> None:
        self.scene, self.poser = scene, poser
        self.period_s = 1.0 / rate_hz                           #: how often the stream is read and drawn
        self.reader = StreamReader(name)
        self.tools: dict[int, np.ndarray | None] = {0: None}   #: tool number -> its offset from the flange (4x4)
        self.lines: list[str] = []                              #: the program's source lines (the caption)
        self.process_caption = ""
        self.process = ProcessOverlay()                          #: the traced signals' points, coloured
        self.updates = 0                                        #: states drawn (the benchmark's update rate)
        self._last: tuple[np.ndarray, Any, np.ndarray] | None = None  #: the newest row drawn, its geoms and flange
        self._stale = False                                     #: the caption's words changed since it was drawn
        if poser is not None:  # the cell travels once, in the poser: its geoms are drawn from it here
            scene.add_cell(poser.shapes(), poser.poses(poser.qpos))

    def set_tool(self, number: int, tool: np.ndarray | None) -> None:
        self.tools[number] = tool

    def set_lines(self, lines: list[str]) -> None:
        self.lines, self._stale = lines, True

    def set_process(self, caption: str) -> None:
        self.process_caption, self._stale = caption, True

    def _flange(self, row: np.ndarray) -> np.ndarray:
        if self.poser is not None:
            return self.poser.flange(row[PAYLOAD:])  # type: ignore[no-any-return]
        flange = np.eye(4)
        flange[:3, :] = row[PAYLOAD:PAYLOAD + 12].reshape(3, 4)
        return flange

    def _tcp(self, flange: np.ndarray, row: np.ndarray) -> np.ndarray:
        tool = self.tools.get(int(row[TOOL]))
        return flange if tool is None else flange @ tool

    def poll(self) -> bool:
        """Draw what the run stored since the last poll; False when there was nothing new."""
        rows = self.reader.take()
        if not len(rows):
            if not self._stale or self._last is None:
                return False
            self._show(*self._last)  # the words came after the pose they belong with
            return True
        with self.scene.together():  # one message window, one wake-up of the server's loop: trace, robot, caption
            self._draw(rows)
        return True

    def _draw(self, rows: np.ndarray) -> None:
        """The trace's new points, the process traces, and the robot and caption at the newest row."""
        trace = []
        for number, row in enumerate(rows, start=1 - len(rows)):
            if number < 0:
                frames, flange = None, self._flange(row)
            else:  # the last row is drawn whole: its geoms come from the same forward kinematics as its flange
                frames, flange = self._place(row)
            tcp = self._tcp(flange, row)[:3, 3].copy()
            trace.append(tcp)
            self.process.sample(dict(zip(TRACED, row[SIGNALS:PAYLOAD])), tcp)
        self.scene.extend_trace(trace)
        for name, points, colours in self.process.take_points():
            self.scene.extend_process(name, points, colours)
        self._show(rows[-1], frames, flange)

    def _place(self, row: np.ndarray) -> tuple[Any, np.ndarray]:
        """The geoms (None without a cell) and the flange at a row."""
        if self.poser is not None:
            return self.poser.place(row[PAYLOAD:], float(row[TIME]))  # type: ignore[no-any-return]
        return None, self._flange(row)

    def _show(self, last: np.ndarray, frames: Any, flange: np.ndarray) -> None:
        """The robot, the flange and the caption at one row (placed by the caller)."""
        self._last, self._stale = (last, frames, flange), False
        line = int(last[LINE])
        self.scene.show(frames, flange, state_caption(float(last[TIME]), line if line > 0 and self.lines else None,
                                                      self.lines, Pose.from_matrix(self._tcp(flange, last)),
                                                      self.process_caption))
        self.updates += 1

    def close(self) -> None:
        self.reader.close()
