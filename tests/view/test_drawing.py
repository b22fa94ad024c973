"""The view's process draws the run's stored rows: the forward kinematics once a row, the caption and the trace."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from multiprocessing import resource_tracker
from typing import Any

import numpy as np
import pytest

pytest.importorskip("viser", reason="the 3D view is the [view] extra")

from orc_rpl.executive.cell_robot import CellRobot  # noqa: E402
from orc_rpl.plant import posing  # noqa: E402
from orc_rpl.plant.posing import CellPoser, live_qpos  # noqa: E402
from orc_rpl.view.drawing import StreamDrawer  # noqa: E402
from orc_rpl.view.live import sim_cell  # noqa: E402
from orc_rpl.view.stream import LINE, PAYLOAD, TIME, TOOL, StreamWriter  # noqa: E402

pytestmark = pytest.mark.sim


class Scene:
    """What the drawer asks of a CellScene, remembered."""

    def __init__(self) -> None:
        self.trace: list[np.ndarray] = []
        self.shown: list[tuple[Any, Any, str]] = []
        self.blocks: list[list[str]] = []  #: the calls made in each `together` block

    @contextmanager
    def together(self) -> Iterator[None]:
        self.blocks.append([])
        yield
        self.blocks.append([])  # what follows the block is not in it

    def _call(self, name: str) -> None:
        if self.blocks:
            self.blocks[-1].append(name)

    def add_cell(self, shapes: Any, poses: Any) -> None:
        pass

    def extend_trace(self, points: list[np.ndarray]) -> None:
        self._call("extend_trace")
        self.trace += points

    def extend_process(self, name: str, points: list[np.ndarray], colours: np.ndarray) -> None:
        pass

    def show(self, frames: Any, flange: Any, caption: str) -> None:
        self._call("show")
        self.shown.append((frames, flange, caption))


def _rows(cell: Any, count: int) -> tuple[StreamWriter, list[np.ndarray]]:
    poser = CellPoser(cell)
    writer = StreamWriter(PAYLOAD + poser.nq, capacity=64)
    qpos = live_qpos(cell).copy()
    stored = []
    for number in range(count):
        row = writer.row()
        row[:] = np.nan
        row[TIME], row[LINE], row[TOOL] = 0.02 * number, -1, 0
        row[PAYLOAD:] = qpos + 0.01 * number
        stored.append(row[PAYLOAD:].copy())
        writer.publish()
    return writer, stored


def test_each_row_costs_one_forward_kinematics(monkeypatch: pytest.MonkeyPatch) -> None:
    cell = sim_cell(CellRobot.virtual())
    writer, stored = _rows(cell, 4)
    scene = Scene()
    drawer = StreamDrawer(Scene(), writer.name, CellPoser(cell))
    resource_tracker.register(writer._memory._name, "shared_memory")  # the reader in this process let go of the writer's block
    drawer.scene = scene
    calls = []
    kinematics = posing.mujoco.mj_kinematics
    monkeypatch.setattr(posing.mujoco, "mj_kinematics", lambda model, data: (calls.append(1), kinematics(model, data)))
    try:
        assert drawer.poll()
        assert len(calls) == 4, "the forward kinematics once for each row, the last one drawn included"
        # the last row's robot and flange: where a poser of its own puts them
        frames, flange = CellPoser(cell).place(stored[-1])
        shown_frames, shown_flange, caption = scene.shown[-1]
        np.testing.assert_allclose(shown_flange, flange)
        np.testing.assert_allclose(shown_frames.position_m, frames.position_m)
        np.testing.assert_allclose(scene.trace[-1], flange[:3, 3])
        assert caption.startswith("t = 0.06 s")
        assert ["extend_trace", "show"] in scene.blocks, "the trace and the robot go to the browser as one"
        drawer.set_lines(["MOVE ARM TO a"])  # new words, no new row: drawn again without kinematics
        calls.clear()
        assert drawer.poll() and not calls
    finally:
        drawer.close()
        writer.close()
