"""The executive: runs checked programs (scopes, call stack, program pointer, steps, exceptions) on a RobotInterface."""

from __future__ import annotations

from typing import Any

from orc_rpl.executive.executive import Executive, ProgramPointer, run_program
from orc_rpl.executive.machine import Options
from orc_rpl.executive.recording_robot import RecordingRobot
from orc_rpl.executive.signals import RunError, StackEntry

__all__ = ["CellRobot", "Executive", "Options", "ProgramPointer", "RecordingRobot", "RunError", "StackEntry", "run_program"]


def __getattr__(name: str) -> Any:
    # CellRobot brings in the motion core (toppra, MuJoCo): only when someone asks for it.
    if name == "CellRobot":
        from orc_rpl.executive.cell_robot import CellRobot

        return CellRobot
    raise AttributeError(f"module 'orc_rpl.executive' has no attribute {name!r}")
