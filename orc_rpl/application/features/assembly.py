"""Assembly (thesis 2.4, 4.5): CALIBRATE (servo auto-tuning at a location) and the thermal-load software sensor."""

from __future__ import annotations

from orc_rpl.application.declarations import FunctionSpec, ParamSpec
from orc_rpl.application.registry import Registry

ORIGIN = "assembly"


def register(registry: Registry) -> None:
    """Declare CALIBRATE; TUNING is a standard attribute, ROBOT.Thermal a software sensor."""
    registry.add_function(
        FunctionSpec("CALIBRATE", "servo auto-tuning on a short path at the current location; use the result WITH TUNING",
                     (ParamSpec("path", ("path", "position")),), returns="tuning", moves=True, origin=ORIGIN)
    )
