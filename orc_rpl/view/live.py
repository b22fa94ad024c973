"""The view of a run: follows the robot, the planned paths, the positions and the statement, at a steady wall-clock rate."""

from __future__ import annotations

import time
from functools import partial
from typing import Any

import numpy as np

from orc_rpl.executive.executive import Executive
from orc_rpl.plant.shapes import Frames, cell_frames, cell_poses, cell_shapes
from orc_rpl.view.framing import frame_work
from orc_rpl.view.positions import declared_names, world_transforms
from orc_rpl.view.process import ProcessOverlay, ProcessState, process_record
from orc_rpl.view.scene import FLANGE_NODE, CellScene
from orc_rpl.view.sender import Sender
from orc_rpl.world.objects import FLANGE, PREDEFINED
from orc_rpl.world.pose import Pose, shown_pose

#: Updates per second of wall-clock time the view sends at most (the robot, the trace, the caption).
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


class LiveView:
    """Attach to a run (`attach`), listen to its robot (`monitor(robot)`), call `finish()` at the end.

    It reads the plant, the motion layer's planned-path signal and the executive's variables; it commands nothing.
    """

    def __init__(self, scene: CellScene | Any, executive: Executive, robot: Any, world: Any = None,
                 rate_hz: float = RATE_HZ) -> None:
        self.scene, self.executive, self.robot, self.world = scene, executive, robot, world
        self.period_s = 1.0 / rate_hz
        self.updates = 0                          #: updates sent so far (the benchmark's rate)
        self._cell = sim_cell(robot)
        self._names: tuple[str, ...] = ()
        self._seen: dict[str, Any] = {}
        self._labels: set[str] = set()            #: positions of the program on screen (the world's stay)
        self._next_wall_s = 0.0
        self._ticks = 0
        self._trace_new: list[np.ndarray] = []
        self._tool: tuple[Any, np.ndarray | None] = (None, None)
        self._tools_mounted = False                #: a world object rides on the flange: the flange is sent too
        self._lines: tuple[str | None, list[str]] = (None, [])   #: the program's source and its lines (the caption)
        self.process = ProcessOverlay()
        self._listening: list[Any] = []           #: the tick listeners of the robot watched (monitor)
        self.sender = self._sender()

    def _sender(self) -> Any:
        """Who runs the scene's calls: a thread of the view's (the scene may take its time; the cycle never waits)."""
        return Sender()

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
        layer.plan_listeners.append(self._planned)
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
        robot.tick_listeners.append(self.on_tick)
        self._listening = robot.tick_listeners
        return robot

    # -- each motion cycle ---------------------------------------------------------------------

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
        """Hand the robot's pose, the trace, new positions and the caption to the sending thread now.

        Only copies are taken here, in the motion cycle; turning them into what the browser gets (quaternions, text)
        is the sending thread's work.
        """
        self._next_wall_s = time.perf_counter() + self.period_s
        frames = cell_frames(self._cell) if self._cell is not None else None
        flange = self.robot.layer.fk(self.robot.layer.current_q()) if self._tools_mounted else None
        self._show_new_positions()
        if self._trace_new:
            self.sender.always(partial(self.scene.extend_trace, self._trace_new))
            self._trace_new = []
        executive = self.executive
        record = process_record(executive.machine.robot)
        process = self.process.state(record)
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

    def _show_state(self, frames: Frames | None, flange: np.ndarray | None, tcp: Any, time_s: float,
                    line: int | None, lines: list[str], process: str = "") -> None:
        self.scene.show(frames, flange, state_caption(time_s, line, lines, tcp, process))
        self.updates += 1

    def highlight(self, position: str | None = None, move_id: int | None = None) -> None:
        """Show a selected position and a move's planned path (the pendant's selection and program pointer)."""
        self.sender.always(partial(self.scene.highlight, position, move_id))

    def finish(self) -> None:
        """Show the last state of the run, whatever the rate, and wait until it is sent; stop listening."""
        if self.on_tick in self._listening:
            self._listening.remove(self.on_tick)
        self._trace_new.append(self._tcp_m())
        self.update()
        self.sender.close()
        listeners = self.robot.layer.plan_listeners
        if self._planned in listeners:
            listeners.remove(self._planned)
