"""Deburring (thesis 2.1, 4.5): GRINDMOVE with force control normal to the path, GrindingPars."""

from __future__ import annotations

from orc_rpl.application.declarations import AttributeSpec, FunctionSpec, ParamSpec
from orc_rpl.application.features.standard import motion
from orc_rpl.application.registry import Registry
from orc_rpl.syntax.units import DIMENSIONLESS, FORCE, LENGTH

ORIGIN = "deburring"


def register(registry: Registry) -> None:
    """Declare GRINDMOVE and GrindingPars."""
    registry.add_motion(
        motion(
            "GRINDMOVE",
            "grind along a path with force control normal to it; remaining bulges are ground down before going on",
            AttributeSpec("FORCE", (FORCE,), 30.0, "normal grinding force, or a FUNC of s"),
            AttributeSpec("GRINDING", ("any",), None, "GrindingPars(tolerance, max_passes)", aliases=("DEBURRING",)),
            targets=("TO", "ALONG"),
            origin=ORIGIN,
        )
    )
    registry.add_function(
        FunctionSpec(
            "GrindingPars", "grinding parameters: bulges above `tolerance` get up to `max_passes` extra passes",
            (ParamSpec("tolerance", (LENGTH,), 0.0002, required=False), ParamSpec("max_passes", (DIMENSIONLESS,), 4, required=False)),
            returns="any", origin=ORIGIN,
        )
    )
