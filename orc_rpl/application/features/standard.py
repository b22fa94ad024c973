"""The standard feature: MOVE/JMOVE/LMOVE/CMOVE, the standard motion attributes and the built-in functions."""

from __future__ import annotations

from orc_rpl.application.declarations import AttributeSpec, FunctionSpec, MotionSpec, ParamSpec
from orc_rpl.application.registry import Registry
from orc_rpl.syntax.units import ACCELERATION, ANGLE, DIMENSIONLESS, LENGTH, MASS, TIME, VELOCITY

ORIGIN = "standard"

#: Attributes every motion keyword accepts (docs/language.md section 4).
STANDARD_ATTRIBUTES: tuple[AttributeSpec, ...] = (
    AttributeSpec("SPEED", (VELOCITY, DIMENSIONLESS), None,
                  "TCP speed, or a fraction of the maximum (`0.5*Vmax`, `50%`)", aliases=("V", "VELOCITY")),
    AttributeSpec("ACCEL", (ACCELERATION, DIMENSIONLESS), None, "TCP acceleration, or a fraction of the maximum"),
    AttributeSpec("ZONE", ("zone", LENGTH), "FINE", "blend radius at the target, or FINE to stop exactly"),
    AttributeSpec("TIME", (TIME,), None, "requested duration of the motion"),
    AttributeSpec("LOAD", (MASS,), None, "payload carried by the tool"),
    AttributeSpec("TUNING", ("tuning",), None, "a servo tuning made by CALIBRATE"),
    AttributeSpec("PATHCONTROL", ("bool",), None, "path velocity control on (TRUE) or off (FALSE) for this motion; "
                  "default: ROBOT.PathControl", function_ok=False),
    AttributeSpec("KNOWN", ("string",), "completely", "how well the program knows the motion before it starts: "
                  "\"completely\", \"almost\" (sensors correct it a little), \"partly\" (a nominal path only) or "
                  "\"not\" (sensors decide it)", function_ok=False, literal_check=lambda text: known_problem(text)),
)

#: The values of KNOWN (thesis 5.2, `enum mv_spec`): how much the motion depends on external sensors.
KNOWN_VALUES = ("completely", "almost", "partly", "not")


def known_problem(text: str) -> str | None:
    """Why a KNOWN value is refused, or None."""
    if text in KNOWN_VALUES:
        return None
    return "KNOWN must be " + ", ".join(f'"{v}"' for v in KNOWN_VALUES[:-1]) + f' or "{KNOWN_VALUES[-1]}", got "{text}"'


_POSITION = ("position",)
_NUMBER = (DIMENSIONLESS,)
_LENGTH = (LENGTH,)


def motion(keyword: str, doc: str, *extra: AttributeSpec, origin: str = ORIGIN, **options: object) -> MotionSpec:
    """A MotionSpec with the standard attributes plus `extra` ones."""
    return MotionSpec(keyword, doc, STANDARD_ATTRIBUTES + tuple(extra), origin=origin, **options)  # type: ignore[arg-type]


def _p(name: str, *types: object, required: bool = True) -> ParamSpec:
    return ParamSpec(name, tuple(types) or ("any",), required=required)  # type: ignore[arg-type]


def register(registry: Registry) -> None:
    """Declare the standard words (no FORCE: force control belongs to GRINDMOVE, so `MOVE ... WITH FORCE` is a check error)."""
    registry.add_motion(motion("MOVE", "joint-interpolated, time-optimal motion through its VIA points", targets=("TO", "ALONG")))
    registry.add_motion(motion("JMOVE", "alias of MOVE: joint-interpolated motion", targets=("TO", "ALONG")))
    registry.add_motion(motion("LMOVE", "straight-line TCP motion, orientation interpolated", targets=("TO", "ALONG")))
    registry.add_motion(motion("CMOVE", "circular motion through the current position, the VIA point and the target",
                               needs_via=True))
    functions = [
        FunctionSpec("POSE", "a pose: translation and rotation Rz(a)*Ry(b)*Rx(c)",
                     (_p("x", LENGTH), _p("y", LENGTH), _p("z", LENGTH), _p("a", ANGLE), _p("b", ANGLE), _p("c", ANGLE)),
                     returns="pose"),
        FunctionSpec("AXES", "a position with external-axis values: AXES(p, track = 200mm, turn = 90deg)",
                     (_p("p", "pose"),), returns="pose", variadic=True),
        FunctionSpec("JOINTS", "a joint-space position, one value per axis", (_p("q1", ANGLE, LENGTH),), returns="joints",
                     variadic=True),
        FunctionSpec("TRANSL", "a pure translation", (_p("x", LENGTH), _p("y", LENGTH), _p("z", LENGTH)), returns="pose"),
        FunctionSpec("INV", "the inverse transform of a pose", (_p("p", "pose"),), returns="pose"),
        FunctionSpec("OFFS", "a pose displaced along the axes of its frame (RAPID's Offs)",
                     (_p("p", "pose"), _p("dx", LENGTH), _p("dy", LENGTH), _p("dz", LENGTH)), returns="pose"),
        FunctionSpec("RELTOOL", "a pose displaced along its own axes",
                     (_p("p", "pose"), _p("dx", LENGTH), _p("dy", LENGTH), _p("dz", LENGTH)), returns="pose"),
        FunctionSpec("ABS", "absolute value", (_p("x"),)),
        FunctionSpec("ROUND", "round to `digits` decimals (default 0)", (_p("x"), _p("digits", DIMENSIONLESS, required=False))),
        FunctionSpec("SQRT", "square root", (_p("x"),)),
        FunctionSpec("SIN", "sine of an angle", (_p("x", ANGLE, DIMENSIONLESS),), returns=DIMENSIONLESS),
        FunctionSpec("COS", "cosine of an angle", (_p("x", ANGLE, DIMENSIONLESS),), returns=DIMENSIONLESS),
        FunctionSpec("ATAN2", "angle of the vector (x, y)", (_p("y"), _p("x")), returns=ANGLE),
        FunctionSpec("MIN", "the smallest argument", (_p("a"), _p("b")), variadic=True),
        FunctionSpec("MAX", "the largest argument", (_p("a"), _p("b")), variadic=True),
        FunctionSpec("LEN", "number of elements of a list or path, or of characters of a string",
                     (_p("items", "list", "path", "string"),), returns=DIMENSIONLESS),
    ]
    for spec in functions:   # each a function of its arguments alone (AXES too: its requests are turned away later)
        registry.add_function(FunctionSpec(spec.name, spec.doc, spec.params, spec.returns, spec.variadic, origin=ORIGIN,
                                           of_arguments=True))

#: Software sensors readable as `ROBOT.<name>` (docs/language.md section 9); indexed ones take a joint number.
ROBOT_SIGNALS: dict[str, str] = {
    "Joints": "joint angles (list, rad)",
    "Torque": "torque estimate of joint j (`ROBOT.Torque[j]`, N m)",
    "PosError": "position error of the TCP (m)",
    "Thermal": "thermal load of motor j (`ROBOT.Thermal[j]`, 1 = its limit)",
    "PathControl": "path velocity control of the motions that follow (TRUE/FALSE; `ROBOT.PathControl = FALSE` sets it)",
}
