"""Behaviour of the standard words: MOVE/JMOVE/LMOVE/CMOVE as motion requests, the Gripper/Grinder/Switch kinds."""

from __future__ import annotations

import dataclasses
from typing import Any

from orc_rpl.application.features.standard import known_problem
from orc_rpl.application.registry import Registry, default_registry
from orc_rpl.application.runtime import (BehaviourError, Fine, FunctionParam, InstallContext, MotionCall, MotionRequest,
                                        attached)
from orc_rpl.application.standard_functions import IMPLEMENTATIONS
from orc_rpl.syntax.limits import MAX_DURATION_S
from orc_rpl.syntax.units import ACCELERATION, ANGLE, LENGTH, MASS, TIME, VELOCITY, Quantity
from orc_rpl.world.pose import Pose

#: Motion kind of each standard keyword.
KINDS = {"MOVE": "joint", "JMOVE": "joint", "LMOVE": "linear", "CMOVE": "circular"}

#: `ACCEL` given as an acceleration is taken relative to this nominal TCP acceleration.
NOMINAL_ACCEL_M_S2 = 10.0


def _number(value: Any) -> float | None:
    return float(value) if type(value) in (int, float) else None


def _speed(value: Any, override: float) -> tuple[Any, Any]:
    """SPEED as (speed_m_s, speed_fraction): a velocity, a fraction (`50%`), or a FUNC of s giving either."""
    if value is None:
        return None, override
    if isinstance(value, FunctionParam):
        sample = value.fn(0.0)
        if type(sample) is Quantity and sample.dim == VELOCITY:
            return (lambda s: _positive(value.fn(s), VELOCITY, "SPEED") * override), override
        if _number(sample) is not None:
            return None, (lambda s: min(1.0, _fraction(value.fn(s), "SPEED") * override))
        raise BehaviourError(f"SPEED function {value.name} must give a velocity or a fraction")
    if type(value) is Quantity and value.dim == VELOCITY:
        return _positive(value, VELOCITY, "SPEED") * override, override
    return None, min(1.0, _fraction(value, "SPEED")) * override


def _positive(value: Any, dim: Any, what: str) -> float:
    if type(value) is not Quantity or value.dim != dim or not value.value > 0:
        raise BehaviourError(f"{what} must be a positive {'velocity' if dim == VELOCITY else 'value'}, got {value}")
    return value.value


def _fraction(value: Any, what: str) -> float:
    number = _number(value)
    if number is None or not 0 < number <= 1:
        raise BehaviourError(f"{what} as a fraction must be in (0, 1] (e.g. 50%), got {value}")
    return number


def _zone(value: Any) -> float:
    if value is None or isinstance(value, Fine) or value == 0:
        return 0.0
    if type(value) is Quantity and value.dim == LENGTH and value.value >= 0:
        return value.value
    if type(value) in (int, float) and value > 0:
        return float(value)  # a plain number where a length is expected is in metres
    raise BehaviourError(f"ZONE must be a length or FINE, got {value}")


def _quantity(value: Any, dim: Any, what: str) -> float | None:
    if value is None:
        return None
    if isinstance(value, FunctionParam):
        raise BehaviourError(f"{what} cannot be a function")
    if type(value) is Quantity and value.dim == dim and value.value >= 0:
        if dim == TIME and not value.value <= MAX_DURATION_S:
            raise BehaviourError(f"{what} of {value} is longer than the longest allowed, {MAX_DURATION_S:g} s")
        return value.value
    if value == 0:
        return 0.0
    raise BehaviourError(f"{what} must be a {'time' if dim == TIME else 'mass'} >= 0, got {value}")


def standard_motion(call: MotionCall) -> MotionRequest:
    """MOVE/JMOVE (joint), LMOVE (line), CMOVE (circle through the VIA point) as one motion request."""
    kind = KINDS[call.keyword]
    attrs = call.attributes
    if call.path is not None:
        target, via = call.path[-1], tuple(call.path[:-1]) + tuple(call.via)
    else:
        target, via = call.target, call.via
    if target is None:
        raise BehaviourError("needs a TO target or an ALONG path")
    if isinstance(target, FunctionParam):
        kind = "function"  # a path in function space: the FUNC of s gives the TCP pose, from the TCP at s = 0
        if target.variable == "t" and not _quantity(attrs.get("TIME"), TIME, "TIME"):
            raise BehaviourError(f"FUNC {target.name}(t) is a function of time: give the motion's duration, "
                                 "WITH TIME = 5s")
    elif kind != "joint" and type(target) is not Pose:
        raise BehaviourError("a Cartesian motion needs a pose as its target, not a joint position")
    if kind == "circular" and (len(via) != 1 or type(via[0]) is not Pose):
        raise BehaviourError("CMOVE needs exactly one VIA pose: the circle passes through it")
    speed_m_s, speed_fraction = _speed(attrs.get("SPEED"), call.speed_override)
    accel = attrs.get("ACCEL")
    if accel is None:
        accel_fraction = 1.0
    elif type(accel) is Quantity and accel.dim == ACCELERATION:
        accel_fraction = min(1.0, max(1e-3, accel.value / NOMINAL_ACCEL_M_S2))
    else:
        accel_fraction = _fraction(accel, "ACCEL")
    # an override slows the whole motion down in time: speeds scale with it, accelerations with its square
    accel_fraction = max(1e-4, accel_fraction * call.speed_override ** 2)
    duration = _quantity(attrs.get("TIME"), TIME, "TIME")
    return MotionRequest(
        keyword=call.keyword, kind=kind, target=target, via=tuple(via), tool=call.tool,
        speed_m_s=speed_m_s, speed_fraction=speed_fraction, accel_fraction=accel_fraction,
        zone_m=_zone(attrs.get("ZONE")), time_s=duration or None,
        load_kg=_quantity(attrs.get("LOAD"), MASS, "LOAD") or 0.0, tuning=attrs.get("TUNING"), until=call.until,
        path_control=attrs.get("PATHCONTROL"), known=_known(attrs.get("KNOWN")),
    )


def _known(value: Any) -> str:
    if value is None:
        return "completely"
    problem = known_problem(value) if isinstance(value, str) else "KNOWN must be a string such as \"almost\""
    if problem is not None:
        raise BehaviourError(problem)
    return value


def _angle(value: Any, what: str) -> float:
    if type(value) is Quantity and value.dim == ANGLE:
        return value.value
    if value == 0:
        return 0.0
    raise BehaviourError(f"{what} must be an angle, got {value}")


class Gripper:
    """A two-state gripper on a digital output, or on a servo of the arm's bus: `.Open`, `.Close`, `.Closed`."""

    def __init__(self, context: InstallContext) -> None:
        self._context = context
        attrs = context.attributes
        self._channel = attrs.get("CLOSE")
        self._servo = attrs.get("SERVO")
        if (self._channel is None) == (self._servo is None):
            raise BehaviourError(f"INSTALL {context.name} AS Gripper needs WITH CLOSE = DigOut[n], "
                                 "or WITH SERVO = id WITH OPEN = angle WITH CLOSED = angle (one of the two)")
        if self._servo is not None:
            if attrs.get("OPEN") is None or attrs.get("CLOSED") is None:
                raise BehaviourError(f"INSTALL {context.name} AS Gripper WITH SERVO needs WITH OPEN = angle WITH CLOSED = angle")
            self._angles_rad = {False: _angle(attrs["OPEN"], "OPEN"), True: _angle(attrs["CLOSED"], "CLOSED")}
            self._current_a = float(attrs.get("GRIP_CURRENT", 0.5))
        self._closed = False
        self._state = attached(context.robot, "grippers_closed", dict) if context.robot is not None else {}
        self._state[context.name] = False  # what IDENTMOVE asks: is anything held?
        self._holding = False

    def _servo_to(self, closed: bool) -> None:
        holding = self._context.robot.drive_gripper(int(self._servo), self._angles_rad[closed], self._current_a)
        self._closed = closed
        self._holding = bool(holding) and closed

    def Open(self) -> None:  # noqa: N802 - the language's method names
        self._state[self._context.name] = False
        if self._servo is not None:
            return self._servo_to(False)
        self._context.write(self._channel, 0)

    def Close(self) -> None:  # noqa: N802
        self._state[self._context.name] = True
        if self._servo is not None:
            return self._servo_to(True)
        self._context.write(self._channel, 1)

    def Closed(self) -> bool:  # noqa: N802
        if self._servo is not None:
            return self._closed
        return bool(self._context.read(self._channel))

    def Holding(self) -> bool:  # noqa: N802
        """TRUE when the last Close of a servo gripper stopped on an object, squeezing it at GRIP_CURRENT."""
        return self._holding


class Grinder:
    """A grinding spindle on a digital output: `.On`, `.Off`."""

    def __init__(self, context: InstallContext) -> None:
        self._context = context
        self._channel = context.attributes.get("SPINDLE")
        if self._channel is None:
            raise BehaviourError(f"INSTALL {context.name} AS Grinder needs WITH SPINDLE = DigOut[n]")

    def On(self) -> None:  # noqa: N802
        self._context.write(self._channel, 1)

    def Off(self) -> None:  # noqa: N802
        self._context.write(self._channel, 0)


class Switch:
    """A digital input read as a sensor: `.State` is 1 when closed."""

    def __init__(self, context: InstallContext) -> None:
        self._context = context
        self._channel = context.attributes.get("INPUT")
        if self._channel is None:
            raise BehaviourError(f"INSTALL {context.name} AS Switch needs WITH INPUT = DigIn[n]")

    def State(self) -> int:  # noqa: N802
        return int(self._context.read(self._channel))


FACTORIES = {"Gripper": Gripper, "Grinder": Grinder, "Switch": Switch}


def install_standard_behaviour(registry: Registry) -> Registry:
    """Fill the behaviour slots of the standard words in `registry` (declarations stay as they are)."""
    for keyword in KINDS:
        spec = registry.motions.get(keyword)
        if spec is not None and spec.execute is None:
            registry.motions[keyword] = dataclasses.replace(spec, execute=standard_motion)
    for name, implementation in IMPLEMENTATIONS.items():
        spec = registry.functions.get(name)
        if spec is not None and spec.implementation is None:
            registry.functions[name] = dataclasses.replace(spec, implementation=implementation)
    for name, factory in FACTORIES.items():
        kind = registry.install_kinds.get(name)
        if kind is not None and kind.factory is None:
            registry.install_kinds[name] = dataclasses.replace(kind, factory=factory)
    return registry


#: The built-in application features with behaviour: `module:function` filling their slots in a registry.
APPLICATION_BEHAVIOUR = (
    "orc_rpl.application.features.spot_welding_behaviour:register_behaviour",
    "orc_rpl.application.features.materials_handling_behaviour:register_behaviour",
    "orc_rpl.application.features.sensor_behaviour:register_behaviour",
    "orc_rpl.application.features.arc_welding_behaviour:register_behaviour",
    "orc_rpl.application.features.deburring_behaviour:register_behaviour",
)


def install_application_behaviour(registry: Registry) -> Registry:
    """Fill the behaviour slots of the built-in application features (spot welding, materials handling)."""
    import importlib

    for reference in APPLICATION_BEHAVIOUR:
        module_name, _, function = reference.partition(":")
        getattr(importlib.import_module(module_name), function)(registry)
    return registry


def runtime_registry() -> Registry:
    """The default registry with the standard behaviour filled in: what the executive runs with."""
    return install_application_behaviour(install_standard_behaviour(default_registry()))

