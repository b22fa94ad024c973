"""A program's declared positions, frames and paths as world transforms (read from the executive's variables)."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from orc_rpl.executive.executive import Executive
from orc_rpl.syntax import nodes as n
from orc_rpl.world.pose import Joints, Pose

#: Declarations the view draws as small named frames.
SHOWN_KINDS = ("POS", "PATH", "FRAME")


def declared_names(program: n.Program) -> tuple[str, ...]:
    """Names of the program's POS, PATH and FRAME declarations outside routines, in source order.

    Declarations inside FRAME blocks count (the pendant teaches positions there, each `IN` its block's frame).
    """

    def visit(body: n.Body) -> list[str]:
        names = []
        for stmt in body:
            if isinstance(stmt, n.Declaration) and stmt.kind in SHOWN_KINDS:
                names.append(stmt.name.id)
            elif isinstance(stmt, n.FrameBlock):
                names += visit(stmt.body)
        return names

    return tuple(visit(program.body))


def world_transforms(name: str, value: Any, executive: Executive) -> list[tuple[str, np.ndarray]]:
    """(label, 4x4 world transform) for a position, each element of a path, or a frame; [] for anything else.

    A pose is placed through its on-line frame; joint values at the flange, as the robot would hold them.
    """
    if type(value) is tuple:
        out = []
        for i, item in enumerate(value, start=1):
            out += world_transforms(f"{name}[{i}]", item, executive)
        return out
    if type(value) is Pose:
        return [(name, executive.machine.to_world(value).matrix())]
    if type(value) is Joints:
        layer = getattr(executive.machine.robot, "layer", None)
        if layer is not None:
            return [(name, np.asarray(layer.fk(np.array(value.values, dtype=float))))]
    return []


def evaluate_declarations(program: n.Program, robot: Any, registry: Any, path: str = "<program>", options: Any = None) -> Executive:
    """Run only the program's top-level declarations (nothing moves): their values are then the executive's globals.

    ENUMs and routines come along (a declaration may use them). A declaration that fails leaves the executive
    failed with its error (status "failed", `report()`).
    """
    only = tuple(s for s in program.body if isinstance(s, n.Declaration | n.EnumDecl | n.Routine))
    executive = Executive(dataclasses.replace(program, body=only), robot, registry, path=path, output=lambda line: None,
                          options=options)
    executive.run()
    return executive
