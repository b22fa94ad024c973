"""What watches `orc run` (the progress display, --margins, --video) listens to the robot: the executive drives the
robot itself, never a wrapper in front of its calls, and nothing is left listening after the run."""

from __future__ import annotations

import io
from pathlib import Path
from typing import Any

import pytest

from orc_rpl.cli import main
from orc_rpl.executive.cell_robot import CellRobot
from orc_rpl.executive.executive import Executive
from tests.executive.test_margins import PROGRAM
from tests.plant.test_world_scene import WORLD


class Terminal(io.StringIO):
    """Standard error as a terminal: the progress display shows."""

    def isatty(self) -> bool:
        return True


@pytest.mark.sim
def test_progress_margins_and_video_listen_to_the_robot(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    pytest.importorskip("imageio_ffmpeg", reason="--video is the [view] extra")
    (tmp_path / "cell.yaml").write_text(WORLD)
    (tmp_path / "prog.rpl").write_text(PROGRAM)
    driven: list[Any] = []
    listening: list[int] = []
    run = Executive.run

    def watched_run(self: Executive, *args: Any, **kwargs: Any) -> Any:
        if self.path == str(tmp_path / "prog.rpl"):  # the run itself, not the declarations run to aim the camera
            robot = self.machine.robot
            driven.append(robot)
            listening.append(len(robot.tick_listeners) if isinstance(robot, CellRobot) else 0)
        return run(self, *args, **kwargs)

    monkeypatch.setattr(Executive, "run", watched_run)
    terminal = Terminal()
    monkeypatch.setattr("sys.stderr", terminal)
    code = main(["run", str(tmp_path / "prog.rpl"), "--world", str(tmp_path / "cell.yaml"), "--margins",
                 "--video", str(tmp_path / "run.mp4")])
    assert code == 0, terminal.getvalue()
    assert "running " in terminal.getvalue(), "the progress display showed"
    assert "margins: clearance:" in terminal.getvalue()
    assert len(driven) == 1 and type(driven[0]) is CellRobot, "the executive drives the robot itself"
    assert listening == [3], "the progress display, the margins and the video listen to its motion cycles"
    assert len(driven[0].tick_listeners) == 0 and len(driven[0].submit_listeners) == 0, "nothing listens after the run"
