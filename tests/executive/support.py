"""Helpers for executive tests: run program text on the recording robot and collect what it printed."""

from __future__ import annotations

import textwrap

from orc_rpl.executive.executive import Executive
from orc_rpl.executive.machine import Options
from orc_rpl.executive.recording_robot import RecordingRobot
from orc_rpl.syntax.parser import parse


def execute(text: str, robot: RecordingRobot | None = None, tracing: bool = False, registry: object = None,
            **options: object) -> Executive:
    """Parse and run `text` to its end on a recording robot (no MuJoCo); `tracing` as the pendant runs it."""
    source = textwrap.dedent(text).lstrip("\n")
    executive = Executive(parse(source, "test.rpl"), robot or RecordingRobot(), registry,  # type: ignore[arg-type]
                          path="test.rpl", source=source, output=lambda line: None,
                          options=Options(**options) if options else None)  # type: ignore[arg-type]
    executive.tracing = tracing
    executive.run()
    return executive


def prints(text: str, tracing: bool = False) -> list[str]:
    """The PRINT lines of a program that must run without error."""
    executive = execute(text, tracing=tracing)
    assert executive.status in ("finished", "stopped"), executive.report()
    return executive.prints
