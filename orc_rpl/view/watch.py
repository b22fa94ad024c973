"""Watching a run: the 3D view and the video around one executive, opened before it starts and closed after it ends."""

from __future__ import annotations

import sys
from pathlib import Path
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass
from typing import Any, TextIO

import numpy as np

from orc_rpl.executive.cell_robot import CellRobot
from orc_rpl.executive.executive import Executive
from orc_rpl.view.framing import frame_work
from orc_rpl.plant.shapes import cell_poses, cell_shapes
from orc_rpl.view.live import sim_cell
from orc_rpl.view.positions import declared_names, evaluate_declarations, world_transforms
from orc_rpl.view.remote import ViewProcess
from orc_rpl.view.streamed import StreamedView
from orc_rpl.view.server import DEFAULT_HOST, DEFAULT_PORT
from orc_rpl.view.video import VideoRecorder
from orc_rpl.world import World, load_world
from orc_rpl.world.objects import FLANGE, PREDEFINED
from orc_rpl.syntax.files import declared_world, is_offline

#: How long an interactive `--view` run waits for a browser to open the page before it starts anyway.
BROWSER_WAIT_S = 60.0


@dataclass(frozen=True, slots=True)
class Watching:
    """What to show of a run: the 3D view (where it listens) and/or a video file."""

    view: bool = False
    host: str = DEFAULT_HOST
    port: int = DEFAULT_PORT
    video: str | None = None
    interactive: bool = False      #: a person at a terminal: wait for the browser, keep the page open at the end


@dataclass
class Watchers:
    """What watch() opened: the live view (and its scene, for tests and the pendant), the video recorder."""

    live: StreamedView | None = None
    video: Any = None
    url: str | None = None
    _linger: Any = None

    def linger(self) -> None:
        """At a terminal: keep the page open until Enter (call after the run's summary is printed), then close it."""
        if self._linger is not None:
            self._linger()
            self._linger = None

    def monitor(self, robot: Any) -> None:
        """Let the view and the video listen to the robot's motion cycles until they are closed."""
        if self.live is not None:
            self.live.monitor(robot)
        if self.video is not None:
            self.video.monitor(robot)


def world_of(program_path: str, world_option: str | None) -> World | None:
    """The world a run shows: `--world FILE`, else an off-line program's `# world:` line; None for neither."""
    if world_option is not None and Path(world_option).is_file():
        return load_world(world_option)
    if is_offline(program_path):
        declared = declared_world(program_path, Path(program_path).read_text(encoding="utf-8"))
        if declared is not None and declared.is_file():
            return load_world(declared)
    return None


def work_points(robot: Any, program: Any, world: Any, registry: Any) -> np.ndarray:
    """Points a camera should keep in the picture: the robot's base and flange, the world's objects, the positions.

    The positions come from the program's declarations run on a kinematic twin beforehand: nothing of the run moves.
    """
    layer = robot.layer
    points = [np.zeros(3), layer.fk(layer.current_q())[:3, 3]]
    cell = sim_cell(robot)
    if cell is not None:  # the robot's links as they stand
        poses = cell_poses(cell)
        points += [poses.position_m[s.index] for s in cell_shapes(cell) if s.moves]
    if world is not None:
        points += [world.world_pose(o.name).matrix()[:3, 3] for o in world.objects
                   if o.name not in PREDEFINED and FLANGE not in world.ancestors(o.name)]
    twin = CellRobot.virtual(robot=layer.kin.arm.name, backend="kinematic")
    preview = evaluate_declarations(program, twin, registry)
    values = preview.machine.globals
    for name in declared_names(program):
        if name in values:
            points += [t[:3, 3] for _, t in world_transforms(name, values[name], preview)]
    return np.array(points)


@contextmanager
def watch(executive: Executive, robot: Any, program: Any, world: Any, registry: Any, how: Watching,
          stderr: TextIO = sys.stderr) -> Iterator[Watchers]:
    """Open the view and/or the video for a run, yield them, and close them when the run is over."""
    watchers = Watchers()
    with ExitStack() as stack:
        if how.view:
            server = ViewProcess(how.host, how.port)  # its own process: the motion cycle keeps the interpreter
            if how.interactive:  # closed by linger(), after the summary
                def keep_open_then_close() -> None:
                    _keep_open(stderr)
                    server.close()
                watchers._linger = keep_open_then_close
            else:
                stack.callback(server.close)
            watchers.url = server.url
            stderr.write(f"orc: the 3D view is at {watchers.url}\n")
            stderr.flush()
            watchers.live = StreamedView(server.scene, executive, robot, world)  # the cycle only stores samples
            watchers.live.attach(program)
            if how.interactive:
                stderr.write(f"orc: open it in a browser; the run starts when it connects (at most {BROWSER_WAIT_S:.0f} s)\n")
                server.wait_connected(BROWSER_WAIT_S)
            stack.callback(watchers.live.finish)
        if how.video is not None:
            watchers.video = VideoRecorder(how.video, executive, robot, frame_work(work_points(robot, program, world, registry)))
            stack.callback(watchers.video.close)
        yield watchers


def _keep_open(stderr: TextIO) -> None:
    stderr.write("orc: the run is over; the view stays open until you press Enter\n")
    stderr.flush()
    try:
        sys.stdin.readline()
    except (KeyboardInterrupt, EOFError):
        pass

