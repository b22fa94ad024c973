"""Assembly (thesis 2.4, 4.5): CALIBRATE (servo auto-tuning at a location) and the thermal-load software sensor."""

from __future__ import annotations

from typing import Any

from orc_rpl.application.declarations import FunctionSpec, ParamSpec
from orc_rpl.application.registry import Registry

ORIGIN = "assembly"


def calibrate(*args: Any, **context: Any) -> Any:
    """CALIBRATE's behaviour (`assembly_behaviour.calibrate`), imported when a program first calls it."""
    from orc_rpl.application.features.assembly_behaviour import calibrate as run

    return run(*args, **context)


def register(registry: Registry) -> None:
    """Declare CALIBRATE; TUNING is a standard attribute, ROBOT.Thermal a software sensor (the motion layer's)."""
    registry.add_function(
        FunctionSpec("CALIBRATE", "servo auto-tuning on a short path at the current location; use the result WITH TUNING",
                     (ParamSpec("path", ("path", "position")),), returns="tuning", moves=True, origin=ORIGIN,
                     implementation=calibrate)
    )
