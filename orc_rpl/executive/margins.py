"""The executive's watch on a run's margins: per motion statement, the robot's clearance to the cell and its joints'
distance to their limits, measured during the run on the simulated cell it runs in (`orc run --margins`)."""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from typing import Any

import numpy as np

from orc_rpl.errors import UsageError
from orc_rpl.plant.clearance import DISTMAX_M, TOLERANCE_FRACTION, TOLERANCE_M, Approach, RunClearance
from orc_rpl.robot.robots import ROBOTS
from orc_rpl.syntax.nodes import Span


@dataclass(slots=True)
class _Statement:
    """What one motion statement came to, over every time it ran."""

    span: Span
    joint_margin_rad: float = np.inf
    joint: int = 0            #: 1-based; 0: never sampled


class MarginWatch:
    """Listens to the robot while it is entered (`with`): remembers which statement submitted each move, and after
    every motion cycle in which a move runs samples the clearance (plant.clearance.RunClearance, on the cell's own
    model) and the joint margins of the moment, under that statement. Reads the cell, never changes it: the run is
    the same with or without it."""

    def __init__(self, robot: Any, machine: Any) -> None:
        cell = getattr(getattr(robot.layer.backend, "loop", None), "cell", None)
        if cell is None:
            raise UsageError("--margins: only a run on the simulated cell measures its margins")
        self._robot, self._machine = robot, machine
        self.dt_s = robot.dt_s
        self.clearance = RunClearance(cell)
        spec = ROBOTS.get(cell.robot)
        self._q_min, self._q_max = np.asarray(spec.q_min_rad), np.asarray(spec.q_max_rad)
        self._moves: deque[tuple[Any, Span]] = deque()  #: submitted moves not yet done, with their statements
        self.statements: dict[tuple[int, int], _Statement] = {}

    def __enter__(self) -> MarginWatch:
        self._robot.submit_listeners.add(self.on_submit)
        self._robot.tick_listeners.add(self.on_tick)
        return self

    def __exit__(self, *exc: Any) -> None:
        self._robot.submit_listeners.discard(self.on_submit)
        self._robot.tick_listeners.discard(self.on_tick)

    def on_submit(self, ticket: Any) -> None:
        span = self._machine.motion_span
        for handle in ticket.handles:
            self._moves.append((handle, span))

    def on_tick(self) -> None:
        moves = self._moves
        running = next(((h, span) for h, span in moves if h.started and not h.done), None)
        while moves and moves[0][0].done:  # finished, stopped, or cancelled before it began
            moves.popleft()
        if running is None or running[1] is None:
            return
        span = running[1]
        key = (span.line, span.column)
        statement = self.statements.get(key)
        if statement is None:
            statement = self.statements[key] = _Statement(span)
        self.clearance.sample(key, self._robot.time_s())
        q = self._robot.layer.current_q()  # the joints as the controller measures them
        n = min(len(q), len(self._q_min))
        margins = np.minimum(q[:n] - self._q_min[:n], self._q_max[:n] - q[:n])
        joint = int(np.argmin(margins))
        if margins[joint] < statement.joint_margin_rad:
            statement.joint_margin_rad, statement.joint = float(margins[joint]), joint + 1

    def section(self, program: str) -> dict[str, Any]:
        """The summary's `margins` section: the nearest approach and the smallest joint margin of the run, each with
        its motion statement (file:line), and every motion statement's own."""
        motions = []
        for key, statement in sorted(self.statements.items()):
            entry = {"file": program, "line": statement.span.line, "column": statement.span.column}
            entry.update(_approach(self.clearance.nearest.get(key)))
            entry.update(joint_margin_deg=None if statement.joint == 0 else round(float(np.degrees(
                statement.joint_margin_rad)), 6), joint=statement.joint or None)
            motions.append(entry)
        measured = [m for m in motions if m["clearance_mm"] is not None]
        nearest = min(measured, key=lambda m: m["clearance_mm"], default=None)
        joints = [m for m in motions if m["joint_margin_deg"] is not None]
        tightest = min(joints, key=lambda m: m["joint_margin_deg"], default=None)
        return {
            "rate_hz": round(1.0 / self.dt_s, 6), "beyond_mm": 1000 * DISTMAX_M,
            "tolerance_mm": 1000 * TOLERANCE_M, "tolerance_fraction": TOLERANCE_FRACTION,
            "samples": self.clearance.samples, "measured": self.clearance.measured,
            "clearance": None if nearest is None else {k: nearest[k] for k in (
                "clearance_mm", "file", "line", "column", "robot_body", "obstacle", "time_s")},
            "joint_margin": None if tightest is None else {k: tightest[k] for k in (
                "joint_margin_deg", "joint", "file", "line", "column")},
            "motions": motions,
        }


def _approach(approach: Approach | None) -> dict[str, Any]:
    if approach is None:  # nothing within DISTMAX_M
        return {"clearance_mm": None, "robot_body": None, "obstacle": None, "time_s": None}
    return {"clearance_mm": round(1000 * approach.distance_m, 3), "robot_body": approach.robot_body,
            "obstacle": approach.obstacle, "time_s": round(approach.time_s, 6)}


def margin_lines(section: dict[str, Any] | None) -> list[str]:
    """The margins in a line each, for the human summary."""
    if section is None:
        return []
    near, joint = section["clearance"], section["joint_margin"]
    lines = [f"clearance: nothing within {section['beyond_mm']:.0f} mm" if near is None else
             f"clearance: {near['clearance_mm']:.1f} mm, {near['robot_body']} to {near['obstacle']} at "
             f"t = {near['time_s']:.3f} s ({near['file']}:{near['line']})"]
    if joint is not None:
        lines.append(f"joint margin: {joint['joint_margin_deg']:.1f} deg on j{joint['joint']} "
                     f"({joint['file']}:{joint['line']})")
    return lines
