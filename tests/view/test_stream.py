"""The run's samples in shared memory: never read half written, complete and in order, the latest drawn."""

from __future__ import annotations

import subprocess
import sys
import threading
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from orc_rpl.view.stream import StreamReader

ROOT = Path(__file__).resolve().parents[2]
#: A writer in a process of its own, as the run is: each row holds its number in every column, stored in pieces, so a
#: reader that caught a row half written would see two numbers in it. Wide rows make the reader's copy and the
#: writer's row take long enough to overlap often.
WRITER = """
import sys
from orc_rpl.view.stream import StreamWriter
rows, capacity, width = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3])
writer = StreamWriter(width=width, capacity=capacity)
print(writer.name, flush=True)
sys.stdin.readline()
for number in range(rows):
    row = writer.row()
    for column in range(0, width, 64):
        row[column:column + 64] = number
    writer.publish()
print("written", flush=True)
sys.stdin.readline()
writer.close()
"""


def _read_while_written(rows: int, capacity: int, width: int) -> tuple[np.ndarray, int]:
    """Start the writer, read while it writes until every row was taken or lost; the rows read and the rows lost."""
    writer = subprocess.Popen([sys.executable, "-c", WRITER, str(rows), str(capacity), str(width)], cwd=ROOT, text=True,
                              stdin=subprocess.PIPE, stdout=subprocess.PIPE)
    try:
        reader = StreamReader(writer.stdout.readline().strip())  # type: ignore[union-attr]
        writer.stdin.write("go\n")  # type: ignore[union-attr]
        writer.stdin.flush()  # type: ignore[union-attr]
        taken = []
        while reader.read < rows:
            taken.append(reader.take())
        assert writer.stdout.readline().strip() == "written"  # type: ignore[union-attr]
        lost = reader.lost
        reader.close()
        writer.stdin.write("close\n")  # type: ignore[union-attr]
        writer.stdin.flush()  # type: ignore[union-attr]
        assert writer.wait(timeout=60) == 0
    finally:
        if writer.poll() is None:
            writer.kill()
            writer.wait()
    return np.concatenate(taken), lost


def test_a_row_being_overwritten_is_never_shown() -> None:
    # a ring of 2 rows: the reader falls behind by a ring again and again, and copies rows the writer overwrites
    read, lost = _read_while_written(20_000, 2, 4096)
    assert len(read) + lost == 20_000
    assert (read == read[:, :1]).all(), "a row mixes two samples"
    numbers = read[:, 0]
    assert (np.diff(numbers) > 0).all(), "rows out of order or twice"


def test_every_sample_arrives_in_order_while_the_ring_is_not_outrun() -> None:
    read, lost = _read_while_written(20_000, 32_768, 8)
    assert lost == 0
    np.testing.assert_array_equal(read[:, 0], np.arange(20_000))
    assert (read == read[:, :1]).all()


pytest.importorskip("viser", reason="the 3D view is the [view] extra")

from orc_rpl.application.standard_behaviour import runtime_registry  # noqa: E402
from orc_rpl.executive.cell_robot import CellRobot  # noqa: E402
from orc_rpl.executive.executive import Executive  # noqa: E402
from orc_rpl.plant.posing import CellPoser  # noqa: E402
from orc_rpl.plant.shapes import Shape, cell_poses  # noqa: E402
from orc_rpl.transform.loading import load_program  # noqa: E402
from orc_rpl.view.live import sim_cell  # noqa: E402
from orc_rpl.view.remote import ViewProcess  # noqa: E402
from orc_rpl.view.streamed import StreamedView  # noqa: E402
from orc_rpl.world.pose import shown_pose  # noqa: E402

PROGRAM = """\
TOOL gripper = POSE(0, 0, 100mm, 0, 0, 0)
POS a = POSE(600mm, -250mm, 450mm, 0, 180deg, 0)
POS b = POSE(650mm, 250mm, 450mm, 0, 180deg, 0)
LMOVE gripper TO a
MOVE gripper TO b
"""


class Counted:
    """A view's scene that remembers the messages sent through it (name and arguments) and passes them on."""

    def __init__(self, scene: Any) -> None:
        self.scene, self.sent = scene, []

    def __getattr__(self, name: str) -> Any:
        call = getattr(self.scene, name)

        def counted(*args: Any) -> Any:
            self.sent.append((name, args))
            return call(*args)
        return counted


def _carries_the_cell(args: tuple[Any, ...]) -> bool:
    """A message's arguments hold the compiled cell (a poser of it) or its geoms."""
    return any(isinstance(a, CellPoser) or (isinstance(a, tuple) and a and isinstance(a[0], Shape)) for a in args)


@pytest.mark.sim
def _threads_started_here(monkeypatch: pytest.MonkeyPatch) -> list[threading.Thread]:
    """The threads this test's own thread starts from now on (a thread another test left behind, e.g. a Dask
    cluster's still shutting down, may start threads of its own meanwhile: those are not the view's)."""
    started: list[threading.Thread] = []
    start = threading.Thread.start
    here = threading.current_thread()

    def recorded(thread: threading.Thread) -> None:
        if threading.current_thread() is here:
            started.append(thread)
        start(thread)

    monkeypatch.setattr(threading.Thread, "start", recorded)
    return started


def test_the_views_process_draws_the_runs_latest_pose_from_the_stream(tmp_path: Path,
                                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "two.rpl"
    path.write_text(PROGRAM, encoding="utf-8")
    source, program = load_program(path)
    robot = CellRobot.virtual(record=True)
    executive = Executive(program, robot, runtime_registry(), path=str(path), source=source, output=lambda line: None)
    server = ViewProcess("127.0.0.1", 0)
    try:
        started = _threads_started_here(monkeypatch)
        scene = Counted(server.scene)
        view = StreamedView(scene, executive, robot)
        view.attach(program)
        assert sum(_carries_the_cell(args) for _, args in scene.sent) == 1, "the cell is sent once"
        assert view.monitor(robot) is robot, "the executive drives the robot itself, no wrapper"
        assert not started, "the view starts no thread in the run's process"
        assert executive.run() == "finished"
        view.finish()
        shown = server.scene.snapshot()
    finally:
        server.close()
    poses = cell_poses(sim_cell(robot))  # where the plant has the robot's links at the end
    assert shown.moving
    for index, node in shown.moving.items():
        np.testing.assert_allclose(node.position, poses.position_m[index], atol=1e-6)
        np.testing.assert_allclose(np.abs(np.dot(node.wxyz, poses.wxyz[index])), 1.0, atol=1e-6)
    # the trace: from where the robot stood to where the recording's last joints put the gripper's TCP
    tool = executive.machine.last_tool.matrix()
    recording = robot.layer.logger.recording()
    np.testing.assert_allclose(shown.trace_m[-1], robot.layer.fk(recording.signals["q"][-1], tool)[:3, 3], atol=1e-6)
    assert len(shown.trace_m) >= robot.time_s() / (5 * robot.dt_s)  # a point every five motion cycles
    # the caption: the last time, the statement, the TCP as orc run shows it
    assert shown.caption.startswith(f"t = {robot.time_s():.2f} s · line 5: MOVE gripper TO b")
    assert f"TCP {shown_pose(robot.tcp_pose(executive.machine.last_tool)).text()}" in shown.caption
    assert view.updates >= 1
