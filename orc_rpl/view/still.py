"""A still view: the cell at home, a world's objects and frames and a program's declared positions; nothing runs."""

from __future__ import annotations

from typing import Any

from orc_rpl.errors import OrcError
from orc_rpl.executive.cell_robot import CellRobot
from orc_rpl.executive.machine import Options
from orc_rpl.syntax import nodes as n
from orc_rpl.view.live import LiveView
from orc_rpl.view.positions import evaluate_declarations
from orc_rpl.view.scene import CellScene


def show_still(server: Any, world: Any, program: n.Program | None, registry: Any, robot: str, caption: str,
               path: str = "<program>") -> LiveView:
    """Draw the still view on `server`; an OrcError when a declaration of the program (at `path`) cannot be evaluated."""
    cell_robot = CellRobot.virtual(robot=robot)
    shown = program if program is not None else n.Program(body=())
    options = None
    if world is not None and world.moving_frames():  # frames on a positioner: where its axes are at home
        cell_robot.attach_world(world)
        options = Options(cell_world=world)
    executive = evaluate_declarations(shown, cell_robot, registry, path, options)
    if executive.status == "failed":
        raise OrcError(executive.report())
    view = LiveView(CellScene(server), executive, cell_robot, world)
    view.attach(shown)  # drawn when this returns: nothing moves, nothing runs on
    layer = cell_robot.layer
    view.scene.show(None, layer.fk(layer.current_q()), caption)  # the tools on the flange where it stands
    return view
