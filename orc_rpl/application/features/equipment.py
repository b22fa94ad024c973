"""General equipment and sensors: Gripper, Grinder, Switch, ForceSensor and the LaserDistance sensor."""

from __future__ import annotations

from orc_rpl.application.declarations import AttributeSpec, InstallKindSpec, MethodSpec
from orc_rpl.application.registry import Registry
from orc_rpl.motion.ports import port_problem
from orc_rpl.syntax.units import ANGLE, DIMENSIONLESS, FORCE, LENGTH

ORIGIN = "equipment"

#: An IO channel such as `DigOut[3]` is written as an indexed name; the checker sees "any".
IO_CHANNEL = ("any",)
PORT = AttributeSpec("PORT", ("string",), "sim", "\"sim\" for the simulated cell, or a serial device such as \"/dev/ttyUSB0\"",
                     function_ok=False, literal_check=port_problem)


def register(registry: Registry) -> None:
    """Declare the general equipment kinds."""
    kinds = [
        InstallKindSpec("Gripper", "a two-state gripper driven by a digital output or by a servo on the arm's bus",
                        (AttributeSpec("CLOSE", IO_CHANNEL, None, "digital output that closes the gripper", function_ok=False),
                         AttributeSpec("SERVO", (DIMENSIONLESS,), None, "id of the gripper's servo on the arm's bus",
                                       function_ok=False),
                         AttributeSpec("OPEN", (ANGLE,), None, "the servo's angle when open (with SERVO)", function_ok=False),
                         AttributeSpec("CLOSED", (ANGLE,), None, "the servo's angle when closed (with SERVO)",
                                       function_ok=False),
                         AttributeSpec("GRIP_CURRENT", (DIMENSIONLESS,), 0.5,
                                       "current (A) at which the servo stops squeezing (with SERVO)", function_ok=False)),
                        (MethodSpec("Open", "open the gripper"), MethodSpec("Close", "close the gripper"),
                         MethodSpec("Closed", "TRUE while the gripper is closed", returns="bool"),
                         MethodSpec("Holding", "TRUE when the last Close of a servo gripper stopped on an object "
                                               "(squeezing it at GRIP_CURRENT)", returns="bool"))),
        InstallKindSpec("Grinder", "a grinding spindle driven by a digital output",
                        (AttributeSpec("SPINDLE", IO_CHANNEL, None, "digital output that runs the spindle", function_ok=False),
                         AttributeSpec("FORCE_IN", IO_CHANNEL, None, "analog input of a force flange's normal force (N); "
                                       "with STROKE, GRINDMOVE presses through the flange (without them the arm "
                                       "presses and reads the force from its motor torques)", function_ok=False),
                         AttributeSpec("STROKE", IO_CHANNEL, None, "analog output of a force flange's stroke (m, toward "
                                       "the part)", function_ok=False)),
                        (MethodSpec("On", "start the spindle"), MethodSpec("Off", "stop the spindle"),
                         MethodSpec("Bulges", "number of bulges GRINDMOVE has caught on this robot so far",
                                    returns=DIMENSIONLESS),
                         MethodSpec("Left", "the highest burr GRINDMOVE's last pass measured on a caught bulge "
                                    "(0 when none was caught)", returns=LENGTH))),
        InstallKindSpec("Switch", "a digital input read as a sensor",
                        (AttributeSpec("INPUT", IO_CHANNEL, None, "digital input of the switch", function_ok=False),),
                        (MethodSpec("State", "1 when the switch is closed", returns=DIMENSIONLESS),), is_sensor=True),
        InstallKindSpec("ForceSensor", "a force sensor at the flange", (PORT,),
                        (MethodSpec("Force", "the measured force along the tool z axis", returns=FORCE),
                         MethodSpec("Zero", "take the present force as zero (tare)")), is_sensor=True),
        InstallKindSpec("LaserDistance", "a laser distance sensor (seam finding and tracking)",
                        (PORT, AttributeSpec("DUMMY", (LENGTH,), None, "the seam's offset from the beam that a motion "
                                             "computed ahead, before the laser has answered, assumes (the dummy's value; "
                                             "without it the dummy sees no seam)", function_ok=False)),
                        (MethodSpec("On", "switch the laser on"), MethodSpec("Off", "switch the laser off"),
                         MethodSpec("Distance", "the measured distance", returns=LENGTH),
                         MethodSpec("EdgeDetected", "TRUE while an edge is under the laser", returns="bool")),
                        is_sensor=True),
    ]
    for kind in kinds:
        registry.add_install_kind(InstallKindSpec(kind.name, kind.doc, kind.attributes, kind.methods, kind.is_sensor, ORIGIN))
