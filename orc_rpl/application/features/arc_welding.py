"""Arc welding (thesis 2.3, 4.5): RecordSeam, OptimalSpeed, Tracking, TRACKMOVE with a laser sensor, SeamLost."""

from __future__ import annotations

from orc_rpl.application.declarations import AttributeSpec, FunctionSpec, InstallKindSpec, MethodSpec, ParamSpec
from orc_rpl.application.features.standard import motion
from orc_rpl.application.registry import Registry
from orc_rpl.syntax.units import VELOCITY

ORIGIN = "arc_welding"


def register(registry: Registry) -> None:
    """Declare the arc-welding words."""
    registry.add_install_kind(
        InstallKindSpec("ArcWelder", "arc-welding power source switched by a digital output",
                        (AttributeSpec("ARC", ("any",), None, "digital output that strikes the arc", function_ok=False),),
                        (MethodSpec("On", "strike the arc"), MethodSpec("Off", "stop the arc")), origin=ORIGIN)
    )
    registry.add_motion(
        motion("TRACKMOVE", "seam tracking with a laser sensor; raises SeamLost when the seam is lost",
               AttributeSpec("SENSOR", ("installed:LaserDistance", "any"), None, "the installed LaserDistance sensor",
                             function_ok=False),
               AttributeSpec("TRACKING", ("any",), None, "tracking parameters made by Tracking, or a gain in (0, 1] by hand", function_ok=False),
               targets=("TO", "ALONG"), origin=ORIGIN)
    )
    functions = [
        FunctionSpec("RecordSeam", "move along a path slowly with standard tracking and record the seam",
                     (ParamSpec("path", ("path", "position")),), returns="any", moves=True),
        FunctionSpec("OptimalSpeed", "the best tracking speed for a recorded seam", (ParamSpec("seam"),), returns=VELOCITY),
        FunctionSpec("Tracking", "tracking parameters for a recorded seam at a speed",
                     (ParamSpec("seam"), ParamSpec("speed", (VELOCITY,))), returns="any"),
    ]
    for spec in functions:
        registry.add_function(FunctionSpec(spec.name, spec.doc, spec.params, spec.returns, moves=spec.moves, origin=ORIGIN))
