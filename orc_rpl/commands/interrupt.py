"""Ending a run early: `--timeout` (simulated seconds) and Ctrl-C stop the robot on its path and keep what was recorded."""

from __future__ import annotations

import argparse
import math
from typing import Any

from orc_rpl.errors import UsageError

#: Simulated seconds the robot gets to brake to a standstill on its path after an interruption.
STOP_WITHIN_S = 10.0


def positive_seconds(text: str) -> float:
    """`--timeout 30` -> 30.0; an argparse error naming the option otherwise."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected seconds such as 30, got {text!r}") from None
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be a positive number of seconds, got {text!r}")
    return value


def statement_budget(text: str) -> int:
    """`--statement-budget 5000000` -> 5000000; 0 means no budget."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number of statements, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be 0 (no budget) or more, got {text!r}")
    return value


class TimeLimit:
    """While entered (`with`): after each motion cycle of the robot (it listens to them), asks the executive to pause
    once simulated time reaches `limit_s`."""

    def __init__(self, robot: Any, limit_s: float, executive: Any) -> None:
        self._robot, self._limit_s, self._executive = robot, limit_s, executive
        self.reached = False

    def __enter__(self) -> TimeLimit:
        self._robot.tick_listeners.add(self.on_tick)
        return self

    def __exit__(self, *exc: Any) -> None:
        self._robot.tick_listeners.discard(self.on_tick)

    def on_tick(self) -> None:
        if self._robot.time_s() >= self._limit_s and not self.reached:
            self.reached = True
            self._executive.pause()  # the executive stops at the next motion cycle


def stop_on_path(robot: Any) -> None:
    """Brake the robot along its path to a standstill (bounded in simulated time)."""
    try:
        robot.stop()
        end_s = robot.time_s() + STOP_WITHIN_S
        while robot.pending() > 0 and robot.time_s() < end_s:
            robot.tick()
    except Exception as error:  # the robot could not brake cleanly; what was recorded so far is still kept
        raise UsageError(f"the robot did not stop cleanly: {type(error).__name__}: {error}") from None
