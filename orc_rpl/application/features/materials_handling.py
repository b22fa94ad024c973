"""Materials handling (thesis 2.5, 4.5): IDENTMOVE with IDENT(proc, parts), the destination chosen in motion."""

from __future__ import annotations

from orc_rpl.application.declarations import FunctionSpec, ParamSpec
from orc_rpl.application.features.standard import motion
from orc_rpl.application.registry import Registry

ORIGIN = "materials_handling"


def register(registry: Registry) -> None:
    """Declare IDENTMOVE and IDENT."""
    registry.add_motion(
        motion("IDENTMOVE", "move via a point while identifying the grasped part from recorded torques; the target "
               "depends on the result", output_functions=("IDENT",), origin=ORIGIN)
    )
    registry.add_function(
        FunctionSpec("IDENT", "identify a part: runs the user's FUNC on a recording of 0.2 s of torques",
                     (ParamSpec("proc", ("function",)), ParamSpec("parts", ("list",))), returns="any", origin=ORIGIN)
    )
