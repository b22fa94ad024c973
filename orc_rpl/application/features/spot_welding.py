"""Spot welding (thesis 2.2, 4.5): INSTALL ... AS SpotGun and WELDMOVE with the weld signal fired tau early."""

from __future__ import annotations

from orc_rpl.application.declarations import AttributeSpec, InstallKindSpec, MethodSpec
from orc_rpl.application.features.standard import motion
from orc_rpl.application.registry import Registry
from orc_rpl.syntax.units import DIMENSIONLESS, LENGTH, TIME, VELOCITY

ORIGIN = "spot_welding"


def register(registry: Registry) -> None:
    """Declare SpotGun and WELDMOVE."""
    registry.add_install_kind(
        InstallKindSpec(
            "SpotGun", "a spot-welding gun: closes on a digital output, reports a good weld on a digital input",
            (
                AttributeSpec("CLOSE", ("any",), None, "digital output that closes the gun and starts the weld", function_ok=False),
                AttributeSpec("WELD_OK", ("any",), None, "digital input set by the welder when the weld is good", function_ok=False),
                AttributeSpec("REACTION", (TIME,), 0.08, "time from the close signal until the gun is closed", function_ok=False),
                AttributeSpec("WELD_TIME", (TIME,), 0.2, "welding time after the gun has closed", function_ok=False),
                AttributeSpec("MAX_SPEED", (VELOCITY,), 0.02,
                              "a weld whose gun closes while the TCP is faster than this is bad (WeldFault)",
                              function_ok=False),
                AttributeSpec("MAX_OFFSET", (LENGTH,), 0.001,
                              "a weld whose gun closes farther than this from the spot is bad (WeldFault)",
                              function_ok=False),
            ),
            (MethodSpec("Open", "open the gun"), MethodSpec("Close", "close the gun"),
             MethodSpec("Welds", "number of good welds (WELD_OK received) made by WELDMOVE since INSTALL",
                        returns=DIMENSIONLESS)),
            origin=ORIGIN,
        )
    )
    registry.add_motion(
        motion("WELDMOVE", "short fast move to a spot, gun closed REACTION before the motion ends, weld, open; WeldFault on a bad weld",
               requires=("SpotGun",), origin=ORIGIN)
    )
