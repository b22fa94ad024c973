"""Local control: per-joint position/velocity loops with feed-forward; internal signals."""

from __future__ import annotations

from typing import Any

from orc_rpl.servo.control import JointServo, ServoGains, ServoTuning

__all__ = ["JointServo", "ServoGains", "ServoLoop", "ServoState", "ServoTuning"]


def __getattr__(name: str) -> Any:
    # The loop owns the MuJoCo cell: import it only when asked for.
    if name in ("ServoLoop", "ServoState"):
        from orc_rpl.servo import loop

        return getattr(loop, name)
    raise AttributeError(f"module 'orc_rpl.servo' has no attribute {name!r}")
