"""Expressions compiled once into closures over a locals dict: no tree walking while the program runs."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from orc_rpl.executive import operators as ops
from orc_rpl.executive.machine import Machine
from orc_rpl.executive.scope import ProgramScopes, Scope
from orc_rpl.executive.signals import RunError
from orc_rpl.executive.values import FINE, IO_BANKS, ROBOT, Installed, IOBank, Routine, RobotSignals, format_value, type_name
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.units import ANGLE, LENGTH, Quantity, parse_literal, to_si, UNIT_CONSTANTS
from orc_rpl.world.pose import Pose

Compiled = Callable[[dict[str, Any]], Any]

#: The predefined tool with nothing mounted: the bare flange.
ARM_TOOL = Pose(0.0, 0.0, 0.0)


class ExpressionCompiler:
    """Turns expression nodes into closures `f(locals) -> value` bound to one Machine."""

    def __init__(self, machine: Machine, scopes: ProgramScopes) -> None:
        self.m = machine
        self.scopes = scopes

    def compile(self, expr: n.Expression, scope: Scope) -> Compiled:
        method = getattr(self, "_" + type(expr).__name__.lower(), None)
        if method is None:
            raise RunError(f"internal error (a bug in orc_rpl, please report it): cannot run {type(expr).__name__}")
        return method(expr, scope)

    def condition(self, expr: n.Expression, scope: Scope) -> Callable[[dict[str, Any]], bool]:
        """A closure giving TRUE/FALSE; comparisons already give booleans, so they skip the check."""
        f = self.compile(expr, scope)
        if isinstance(expr, n.Binary) and expr.op in ("=", "<>", "<", "<=", ">", ">=", "AND", "OR"):
            return f
        if isinstance(expr, n.Unary) and expr.op == "NOT":
            return f
        truth = ops.truth
        return lambda L: truth(f(L))

    # -- literals --------------------------------------------------------------------------

    def _number(self, expr: n.Number, scope: Scope) -> Compiled:
        try:
            value = parse_literal(expr.text)
        except (KeyError, ValueError):
            raise RunError(f"'{expr.text}' is not a number with a known unit") from None
        return lambda L: value

    def _string(self, expr: n.String, scope: Scope) -> Compiled:
        value = expr.value
        return lambda L: value

    def _boolean(self, expr: n.Boolean, scope: Scope) -> Compiled:
        value = expr.value
        return lambda L: value

    def _listexpr(self, expr: n.ListExpr, scope: Scope) -> Compiled:
        items = [self.compile(item, scope) for item in expr.items]
        return lambda L: tuple(f(L) for f in items)

    # -- names -----------------------------------------------------------------------------

    def _name(self, expr: n.Name, scope: Scope) -> Compiled:
        name = expr.id
        if scope.is_local(name):
            def local(L: dict[str, Any]) -> Any:
                try:
                    return L[name]
                except KeyError:
                    raise RunError(f"'{name}' has no value yet") from None
            return local
        G = self.m.globals
        fallback = self.predefined(name, scope)

        def global_(L: dict[str, Any]) -> Any:
            try:
                return G[name]
            except KeyError:
                return fallback()
        return global_

    def predefined(self, name: str, scope: Scope) -> Callable[[], Any]:
        """What a name means when no variable of the program holds it (yet)."""
        m = self.m
        if name == "HERE":
            frame, in_motion = scope.frame, scope.in_motion
            return lambda: m.here(frame, in_motion)
        constants: dict[str, Any] = {"ARM": ARM_TOOL, "ROBOT": ROBOT, "FINE": FINE, "world": "world", **IO_BANKS}
        if name in constants:
            value = constants[name]
            return lambda: value
        if name in UNIT_CONSTANTS:
            unit = to_si(1, name)
            return lambda: unit
        if name in self.scopes.routines:
            routine = self.scopes.routines[name]
            if routine.kind == "FUNC" and not routine.params:
                span = routine.span
                return lambda: m.call_now(m.routines[name], [], span)
            value = Routine(name, routine.kind, tuple(p.id for p in routine.params))
            return lambda: value
        if name in self.scopes.globals:
            def unset() -> Any:
                raise RunError(f"'{name}' has no value yet (its declaration has not run)")
            return unset

        def undefined() -> Any:
            raise RunError(f"'{name}' is not defined")
        return undefined

    # -- operators -------------------------------------------------------------------------

    def _unary(self, expr: n.Unary, scope: Scope) -> Compiled:
        operand = self.compile(expr.operand, scope)
        if expr.op == "NOT":
            truth = ops.truth
            return lambda L: not truth(operand(L))
        if expr.op == "+":
            return operand
        if isinstance(expr.operand, n.Number):  # a negative literal: fold it
            value = ops.negate(operand({}))
            return lambda L: value
        negate = ops.negate
        return lambda L: negate(operand(L))

    def _binary(self, expr: n.Binary, scope: Scope) -> Compiled:
        left, right = self.compile(expr.left, scope), self.compile(expr.right, scope)
        truth = ops.truth
        if expr.op == "AND":
            return lambda L: truth(left(L)) and truth(right(L))
        if expr.op == "OR":
            return lambda L: truth(left(L)) or truth(right(L))
        fn = ops.BINARY[expr.op]
        return lambda L: fn(left(L), right(L))

    # -- postfix ---------------------------------------------------------------------------

    def _field(self, expr: n.Field, scope: Scope) -> Compiled:
        value = self.compile(expr.value, scope)
        name = expr.name.id
        m = self.m
        if isinstance(expr.value, n.Name) and name in m.options.world_attributes.get(expr.value.id, {}):
            attributes = m.options.world_attributes[expr.value.id]
            return lambda L: attributes[name]  # a soft or spatial attribute of a world object (`pallet.next_row`)
        get_field = ops.get_field

        def field(L: dict[str, Any]) -> Any:
            base = value(L)
            if type(base) is Installed:
                return invoke_method(m, base, name, [])
            if type(base) is RobotSignals:
                return robot_signal(m, name)
            return get_field(base, name)
        return field

    def _index(self, expr: n.Index, scope: Scope) -> Compiled:
        value, index = self.compile(expr.value, scope), self.compile(expr.index, scope)
        m = self.m
        list_index = ops.list_index

        def item(L: dict[str, Any]) -> Any:
            base = value(L)
            i = index(L)
            if type(base) is tuple:
                return base[list_index(base, i)]
            if type(base) is IOBank:
                return m.read_io(base, i)
            if type(base) is str:
                return base[list_index(base, i)]
            raise RunError(f"cannot index {type_name(base)}")
        return item

    def _call(self, expr: n.Call, scope: Scope) -> Compiled:
        positional = [self.compile(a.value, scope) for a in expr.arguments if a.name is None]
        named = {a.name.id: self.compile(a.value, scope) for a in expr.arguments if a.name is not None}
        m = self.m
        span = expr.span
        if isinstance(expr.function, n.Field):
            target, method = self.compile(expr.function.value, scope), expr.function.name.id

            def method_call(L: dict[str, Any]) -> Any:
                obj = target(L)
                if type(obj) is not Installed:
                    raise RunError(f"{type_name(obj)} has no method '{method}'")
                return invoke_method(m, obj, method, [f(L) for f in positional])
            return method_call
        if not isinstance(expr.function, n.Name):
            raise RunError("only a name or a method can be called")
        name = expr.function.id
        if name in self.scopes.routines and not scope.is_local(name):
            routine = self.scopes.routines[name]
            order = [p.id for p in routine.params]

            if routine.kind == "PROC":
                def proc_value(L: dict[str, Any]) -> Any:
                    raise RunError(f"PROC {name} gives no value; call it as a statement, or make it a FUNC")
                return proc_value

            def user_call(L: dict[str, Any]) -> Any:
                args = [f(L) for f in positional]
                if named:
                    args = merge_named(name, order, args, {k: f(L) for k, f in named.items()})
                return m.call_now(m.routines[name], args, span)
            return user_call
        spec = m.registry.functions.get(name)
        if spec is None:
            def unknown(L: dict[str, Any]) -> Any:
                raise RunError(f"'{name}' is not a function")
            return unknown
        implementation = spec.implementation
        given = len(positional) + len(named)
        if given < spec.min_args or (spec.max_args is not None and given > spec.max_args):
            wanted = (f"{spec.min_args}" if spec.max_args == spec.min_args else
                      f"at least {spec.min_args}" if spec.max_args is None else f"{spec.min_args} to {spec.max_args}")

            def arity(L: dict[str, Any]) -> Any:
                raise RunError(f"{name} takes {wanted} argument{'s' if wanted != '1' else ''}, got {given}")
            return arity
        if implementation is None:
            def missing(L: dict[str, Any]) -> Any:
                raise RunError(f"{name} is not implemented yet (feature '{spec.origin}')")
            return missing
        if spec.moves:  # it moves the robot (CALIBRATE): from rest, with the robot and the tool last moved
            def moving(L: dict[str, Any]) -> Any:
                args, kwargs = [f(L) for f in positional], {k: f(L) for k, f in named.items()}
                m.sync_now()
                tool = ARM_TOOL if m.last_tool is None else m.last_tool
                return implementation(*args, robot=m.robot, tool=tool, to_world=m.to_world, **kwargs)
            return moving
        if not named:
            if len(positional) == 1:
                a0 = positional[0]
                return lambda L: implementation(a0(L))
            return lambda L: implementation(*[f(L) for f in positional])
        return lambda L: implementation(*[f(L) for f in positional], **{k: f(L) for k, f in named.items()})


def merge_named(routine: str, order: list[str], args: list[Any], named: dict[str, Any]) -> list[Any]:
    result: list[Any] = list(args) + [_MISSING] * (len(order) - len(args))
    for key, value in named.items():
        if key not in order:
            raise RunError(f"{routine} has no parameter '{key}'")
        result[order.index(key)] = value
    if any(v is _MISSING for v in result):
        raise RunError(f"{routine} needs a value for '{order[result.index(_MISSING)]}'")
    return result


_MISSING = object()


def invoke_method(m: Machine, obj: Installed, method: str, args: list[Any]) -> Any:
    """`obj.method` / `obj.method(args)` on an installed object, through its kind's behaviour."""
    behaviour = obj.behaviour
    fn = getattr(behaviour, method, None) if behaviour is not None and not method.startswith("_") else None
    if fn is None:
        kind = m.registry.install_kinds.get(obj.kind)
        if kind is not None and kind.method(method) is not None:
            raise RunError(f"{obj.kind}.{method} is not implemented yet (feature '{kind.origin}')")
        raise RunError(f"{obj.name} (a {obj.kind}) has no method '{method}'")
    return fn(*args)


def robot_signal(m: Machine, name: str) -> Any:
    """`ROBOT.Joints`, `ROBOT.Torque`, `ROBOT.PosError`, `ROBOT.Thermal`: the software sensors."""
    robot = m.robot
    if name == "Joints":
        return tuple(Quantity(float(q), ANGLE) for q in robot.joints())
    if name == "Torque":
        from orc_rpl.syntax.units import TORQUE

        return tuple(Quantity(float(t), TORQUE) for t in robot.torques())
    if name == "PosError":
        return Quantity(float(robot.position_error_m()), LENGTH)
    if name == "Thermal":
        thermal = getattr(robot, "thermal_loads", None)
        if thermal is None:
            raise RunError("ROBOT.Thermal: this robot has no thermal load estimate")
        return tuple(float(x) for x in thermal())
    if name == "PathControl":
        return bool(getattr(robot, "path_control", False))
    raise RunError(f"ROBOT has no signal '{name}'; it has Joints, Torque, PosError, Thermal, PathControl")


def set_robot_setting(m: Machine, name: str, value: Any) -> None:
    """`ROBOT.PathControl = TRUE|FALSE`: path velocity control for the motions requested from now on."""
    if name != "PathControl":
        raise RunError(f"ROBOT.{name} cannot be assigned; ROBOT.PathControl can")
    if type(value) is not bool:
        raise RunError(f"ROBOT.PathControl takes TRUE or FALSE, got {format_value(value)}")
    setter = getattr(m.robot, "set_path_control", None)
    if setter is None:
        raise RunError("ROBOT.PathControl: this robot has no path velocity controller")
    setter(value)

