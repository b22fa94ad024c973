"""The view of a robot and its program: the cell, the world, the positions and the planned paths drawn and kept as they
are; a run's motion cycles feed its streamed form (view/streamed.py)."""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from typing import Any

import numpy as np

from orc_rpl.executive.executive import Executive
from orc_rpl.listeners import Listeners
from orc_rpl.plant.shapes import cell_poses, cell_shapes
from orc_rpl.view.framing import frame_work
from orc_rpl.view.positions import declared_names, world_transforms
from orc_rpl.view.process import ProcessOverlay, ProcessState
from orc_rpl.view.scene import FLANGE_NODE, CellScene
from orc_rpl.world.objects import FLANGE, PREDEFINED
from orc_rpl.world.pose import Pose, shown_pose

#: Updates per second of wall-clock time the view draws at most (the robot, the trace, the caption).
RATE_HZ = 40.0
#: The TCP trace takes a point every this many motion cycles (simulated time, so it is the same paced or fast).
TRACE_EVERY_TICKS = 5


def sim_cell(robot: Any) -> Any:
    """The simulated MuJoCo cell under a robot, or None (a kinematic robot, real hardware)."""
    loop = getattr(getattr(getattr(robot, "layer", None), "backend", None), "loop", None)
    return getattr(loop, "cell", None)


def statement_caption(executive: Executive, time_s: float) -> str:
    """`t = 1.24 s · line 12: LMOVE gripper TO slot1`: where the program is (the statement it executes or waits at)."""
    pointer = executive.pointer
    lines = executive.source.splitlines() if executive.source is not None else []
    return caption_text(time_s, pointer.line if pointer is not None and lines else None, lines)


def caption_text(time_s: float, line: int | None, lines: list[str]) -> str:
    """The caption from the simulated time and the line the program is at (None: no program line to show)."""
    if line is None:
        return f"t = {time_s:.2f} s"
    text = lines[line - 1].strip() if 0 < line <= len(lines) else ""
    return f"t = {time_s:.2f} s · line {line}: {text}"


def state_caption(time_s: float, line: int | None, lines: list[str], tcp: Pose, process: str = "") -> str:
    """The view's caption: where the program is, the measured TCP as `orc run` shows it, the processes' line."""
    caption = f"{caption_text(time_s, line, lines)}\n\nTCP {shown_pose(tcp).text()}"
    return f"{caption}\n\n{process}" if process else caption


class Direct:
    """Runs the scene's calls at once in the caller's thread (for a scene in the view's own process, each is one
    message into its socket). A view whose scene failed (its process has gone) stops; the run goes on."""

    def __init__(self) -> None:
        self.error: BaseException | None = None

    def always(self, job: Callable[[], None]) -> None:
        if self.error is None:
            try:
                job()
            except Exception as error:  # the view's process is gone: the robot must not stop for it
                self.error = error

    latest = always

    def drain(self) -> None:
        """Nothing waits: each call was sent when it was made."""

    def close(self) -> None:
        """Nothing to stop."""


class LiveView:
    """Attach to a robot and its program (`attach`), call `finish()` at the end. It draws the cell, the world, the
    declared positions (as they are taught and touched up, `update`) and the planned paths, and follows the pendant's
    executive after each edit; it reads the plant, the motion layer's planned-path signal and the executive's
    variables, and commands nothing. By itself it is the still view (`orc view`); a run's view
    (streamed.StreamedView) also listens to the robot's motion cycles (`monitor(robot)` calls its `on_tick`).
    """

    def __init__(self, scene: CellScene | Any, executive: Executive, robot: Any, world: Any = None,
                 rate_hz: float = RATE_HZ) -> None:
        self.scene, self.executive, self.robot, self.world = scene, executive, robot, world
        self.period_s = 1.0 / rate_hz
        self.updates = 0                          #: states drawn so far (the benchmark's rate)
        self._cell = sim_cell(robot)
        self._names: tuple[str, ...] = ()
        self._seen: dict[str, Any] = {}
        self._labels: set[str] = set()            #: positions of the program on screen (the world's stay)
        self._ticks = 0                           #: motion cycles seen
        self._tools_mounted = False                #: a world object rides on the flange: the flange is drawn too
        self.process = ProcessOverlay()
        self._listening: Listeners[[]] = Listeners()  #: the tick listeners of the robot watched (monitor)
        self.sender = self._sender()

    def _sender(self) -> Any:
        """Who runs the scene's calls: at once, in the caller's thread."""
        return Direct()

    # -- setting up ---------------------------------------------------------------------------

    def attach(self, program: Any) -> None:
        """Draw the cell, the world and what is declared so far; listen to the planned paths; aim the camera."""
        self.executive.tracing = True  # the program pointer follows every statement (the caption)
        self._names = declared_names(program)
        self._add_cell()
        layer = self.robot.layer
        reach = [np.zeros(3), layer.fk(layer.current_q())[:3, 3]]
        if self.world is not None:
            reach += self._add_world()
        layer.plan_listeners.add(self._planned)
        self.scene.frame_camera(frame_work(np.array(reach)))
        self.update()

    def _add_cell(self) -> None:
        """The simulated cell's geoms where they stand."""
        if self._cell is not None:
            self.scene.add_cell(cell_shapes(self._cell), cell_poses(self._cell))

    def _add_world(self) -> list[np.ndarray]:
        """Draw the world's objects and named frames; where the objects standing in the cell are (the camera's aim)."""
        world, standing = self.world, []
        for obj in world.objects:
            if obj.name in PREDEFINED:
                continue
            if FLANGE in world.ancestors(obj.name):  # tools ride on the flange
                self._tools_mounted = True
                self.scene.add_object(obj.name, world.relative_pose(obj.name, FLANGE).matrix(), obj.model, FLANGE_NODE)
                continue
            placed = world.world_pose(obj.name).matrix()
            self.scene.add_object(obj.name, placed, obj.model)
            standing.append(placed[:3, 3])
            dotted_names = [f"{obj.name}.{frame.name}" for frame in obj.frames]  # the world's named positions
            dotted_names += [f"{obj.name}.{path.name}[{i}]" for path in obj.paths for i in range(1, len(path.points) + 1)]
            for dotted in dotted_names:
                self.scene.set_position(dotted, world.world_pose(dotted).matrix())
        return standing

    def _planned(self, move_id: int, tcp_m: np.ndarray) -> None:
        """The motion layer's planned-path signal: drawn before the move starts."""
        self.sender.always(partial(self.scene.add_path, move_id, tcp_m))

    def follow(self, executive: Executive, program: Any) -> None:
        """Show another executive of the program from now on (the pendant rebuilds it after every edit): positions
        taught, touched up, renamed or deleted are shown as they now are."""
        self.executive = executive
        executive.tracing = True
        self._names = declared_names(program)
        self._seen = {}
        labels = {label for name in self._names
                  for label, _ in world_transforms(name, executive.machine.globals.get(name), executive)}
        gone, self._labels = self._labels - labels, self._labels & labels
        if gone:
            self.sender.always(partial(self.scene.remove_positions, sorted(gone)))
        self.update()

    def monitor(self, robot: Any) -> Any:
        """Listen to the robot's motion cycles (its `tick_listeners`) until finish(); the robot for the executive to
        drive is the robot itself, no wrapper."""
        robot.tick_listeners.add(self.on_tick)
        self._listening = robot.tick_listeners
        return robot

    def on_tick(self) -> None:
        """One motion cycle of the robot watched (monitor), counted; a run's view stores a sample every few."""
        self._ticks += 1

    def update(self) -> None:
        """Show what changed now: positions declared, taught or touched up."""
        self._show_new_positions()

    def _show_new_positions(self) -> None:
        """Positions declared, taught or touched up since the last look (the variables' values are compared by identity)."""
        values = self.executive.machine.globals
        for name in self._names:
            value = values.get(name)
            if value is not None and value is not self._seen.get(name):
                self._seen[name] = value
                for label, t in world_transforms(name, value, self.executive):
                    self._labels.add(label)
                    self.sender.always(partial(self.scene.show_position, label, t))

    def _show_welds(self, process: ProcessState) -> None:
        for number, weld in enumerate(process.welds, start=process.first_weld):
            self.scene.add_weld(number, weld.position_m, weld.good, weld.reason)

    def highlight(self, position: str | None = None, move_id: int | None = None) -> None:
        """Show a selected position and a move's planned path (the pendant's selection and program pointer)."""
        self.sender.always(partial(self.scene.highlight, position, move_id))

    def finish(self) -> None:
        """Stop listening to the robot's motion cycles and planned paths."""
        self._listening.discard(self.on_tick)
        self.robot.layer.plan_listeners.discard(self._planned)
