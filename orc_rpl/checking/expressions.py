"""Static types of expressions: names resolved, dimensions checked, pose frames followed, calls counted."""

from __future__ import annotations

from collections.abc import Mapping
from functools import lru_cache
from typing import Callable

from orc_rpl.application.declarations import describe_types
from orc_rpl.application.features.standard import ROBOT_SIGNALS
from orc_rpl.application.registry import Registry, suggest
from orc_rpl.checking.symbols import ANY, BOOL, STRING, WORLD, Scope, StaticType, number
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.units import ANGLE, DIMENSIONLESS, LENGTH, Dimension, Quantity, dim_of, parse_literal

Report = Callable[[n.Node, str, str], None]

_POSE_FIELDS = {"x": LENGTH, "y": LENGTH, "z": LENGTH, "a": ANGLE, "b": ANGLE, "c": ANGLE}
_FRAME_KEEPING = {"OFFS", "RELTOOL"}
_INPUTS = {"DigIn", "AnalogIn"}


@lru_cache(maxsize=4096)
def literal_dim(text: str) -> Dimension:
    """The dimension of a number literal."""
    return dim_of(parse_literal(text))


@lru_cache(maxsize=4096)
def literal_type(text: str) -> StaticType:
    """The static type of a number literal."""
    return number(literal_dim(text))


def accepts(types: tuple[object, ...], actual: StaticType) -> bool:
    """Whether a value of static type `actual` fits one of the declared `types`."""
    if actual.kind == "any" or "any" in types:
        return True
    for expected in types:
        if isinstance(expected, Dimension):
            if actual.kind == "number" and (actual.dim is None or actual.dim == expected):
                return True
            # A plain number where a length or an angle is expected is in SI (m, rad), as in world files.
            if actual.kind == "number" and actual.dim == DIMENSIONLESS and expected in (LENGTH, ANGLE):
                return True
        elif expected == "position" and actual.kind in ("pose", "joints"):
            return True
        elif expected == "function" and actual.kind == "routine":
            return True
        elif expected == "zone" and actual.kind == "zone":
            return True
        elif expected == "path" and actual.kind in ("path", "list"):
            return True
        elif isinstance(expected, str) and expected.startswith("installed:"):
            if actual.kind == "installed" and actual.detail == expected.split(":", 1)[1]:
                return True
        elif expected == actual.kind:
            return True
    return False


class ExpressionTyper:
    """Infers static types and reports what is wrong in an expression."""

    def __init__(self, registry: Registry, report: Report) -> None:
        self.registry = registry
        self.report = report
        self.world_attributes: Mapping[str, Mapping[str, object]] = {}   #: the world's soft and spatial attributes
        #: the cell's external axes, name -> "linear" or "rotary" (None: the cell is not known, names are not checked)
        self.external_axes: Mapping[str, str] | None = None
        # One dispatch table instead of a getattr per node: the checker runs on every keystroke of the pendant.
        self._dispatch = {cls: getattr(self, "_" + cls.__name__) for cls in (
            n.Number, n.String, n.Boolean, n.Name, n.ListExpr, n.Field, n.Index, n.Call, n.Unary, n.Binary)}

    def infer(self, expr: n.Expression, scope: Scope, frame: str = WORLD) -> StaticType:
        """The static type of `expr` in `scope`, inside the lexical FRAME `frame`."""
        return self._dispatch[type(expr)](expr, scope, frame)

    def _Number(self, expr: n.Number, scope: Scope, frame: str) -> StaticType:
        return literal_type(expr.text)

    def _String(self, expr: n.String, scope: Scope, frame: str) -> StaticType:
        return STRING

    def _Boolean(self, expr: n.Boolean, scope: Scope, frame: str) -> StaticType:
        return BOOL

    def _Name(self, expr: n.Name, scope: Scope, frame: str) -> StaticType:
        symbol = scope.lookup(expr.id)
        if symbol is None:
            guess = suggest(expr.id, scope.visible_names())
            self.report(expr, f"undefined name '{expr.id}'" + (f"; did you mean '{guess}'?" if guess else ""), "")
            return ANY
        if expr.id == "HERE":
            return StaticType("pose", frame=frame)
        return symbol.type

    def _ListExpr(self, expr: n.ListExpr, scope: Scope, frame: str) -> StaticType:
        items = [self.infer(item, scope, frame) for item in expr.items]
        frames = {t.frame for t in items if t.kind == "pose"}
        if items and all(t.kind == "pose" for t in items) and len(frames) == 1:
            return StaticType("path", frame=frames.pop())
        return StaticType("list")

    def _Field(self, expr: n.Field, scope: Scope, frame: str) -> StaticType:
        owner = self.infer(expr.value, scope, frame)
        field_name = expr.name.id
        if (isinstance(expr.value, n.Name) and owner.kind in ("frame", "pose", "tool") and field_name not in _POSE_FIELDS
                and (owner.kind == "frame" or expr.value.id in self.world_attributes)):
            return self.world_attribute(expr, expr.value.id, field_name)
        if owner.kind == "frame" and field_name in _POSE_FIELDS:
            return number(_POSE_FIELDS[field_name])
        if owner.kind == "pose":
            if field_name not in _POSE_FIELDS:
                self.report(expr.name, f"a pose has no field '{field_name}'; its fields are x, y, z, a, b, c", "")
                return ANY
            return number(_POSE_FIELDS[field_name])
        if owner.kind == "installed" and owner.detail in self.registry.install_kinds:
            kind = self.registry.install_kinds[owner.detail]
            method = kind.method(field_name)
            if method is None:
                guess = suggest(field_name, [m.name for m in kind.methods])
                known = ", ".join(m.name for m in kind.methods)
                self.report(expr.name, f"a {kind.name} has no method or value '{field_name}'"
                            + (f"; did you mean '{guess}'?" if guess else ""), f"{kind.name} offers: {known}")
                return ANY
            if method.returns is None:
                return StaticType("command")
            return number(method.returns) if isinstance(method.returns, Dimension) else StaticType(str(method.returns))
        if owner.kind == "robot":
            if field_name not in ROBOT_SIGNALS:
                guess = suggest(field_name, ROBOT_SIGNALS)
                self.report(expr.name, f"ROBOT has no signal '{field_name}'" + (f"; did you mean '{guess}'?" if guess else ""),
                            "ROBOT offers: " + ", ".join(ROBOT_SIGNALS))
            return ANY
        return ANY

    def world_attribute(self, expr: n.Field, owner: str, name: str) -> StaticType:
        """A soft or spatial attribute of a world object (`pallet.next_row`), checked against the world model."""
        attributes = self.world_attributes.get(owner)
        if attributes is None:
            self.report(expr.name, f"'{owner}' has no field '{name}'; its fields are x, y, z, a, b, c",
                        "soft and spatial attributes of world objects are read with the program's world (--world FILE)"
                        if not self.world_attributes else f"'{owner}' has no soft or spatial attributes in the world model")
            return ANY
        if name not in attributes:
            guess = suggest(name, attributes)
            self.report(expr.name, f"'{owner}' has no attribute '{name}' in the world model"
                        + (f"; did you mean '{guess}'?" if guess else ""), "attributes: " + ", ".join(attributes))
            return ANY
        value = attributes[name]
        if isinstance(value, bool):
            return BOOL
        if isinstance(value, (int, float)):
            return number(DIMENSIONLESS)
        if isinstance(value, Quantity):
            return number(value.dim)
        return STRING if isinstance(value, str) else ANY

    def _Index(self, expr: n.Index, scope: Scope, frame: str) -> StaticType:
        owner = self.infer(expr.value, scope, frame)
        index = self.infer(expr.index, scope, frame)
        if index.kind == "number" and index.dim not in (None, DIMENSIONLESS):
            self.report(expr.index, f"an index must be a number, got {index}", "")
        if owner.kind == "io":
            return number(DIMENSIONLESS)
        if owner.kind == "path" and owner.frame is not None:
            return StaticType("pose", frame=owner.frame)
        return ANY

    def _Call(self, expr: n.Call, scope: Scope, frame: str) -> StaticType:
        arg_types = [self.infer(a.value, scope, frame) for a in expr.arguments]
        if isinstance(expr.function, n.Field):
            owner = self.infer(expr.function, scope, frame)
            return ANY if owner.kind == "command" else owner
        if not isinstance(expr.function, n.Name):
            self.report(expr.function, "only a routine or a function can be called", "")
            return ANY
        name = expr.function.id
        symbol = scope.lookup(name)
        if symbol is None:
            guess = suggest(name, [*scope.visible_names()])
            self.report(expr.function, f"undefined routine or function '{name}'" + (f"; did you mean '{guess}'?" if guess else ""), "")
            return ANY
        if symbol.kind in ("proc", "func"):
            if symbol.params is not None and len(expr.arguments) != symbol.params:
                self.report(expr, f"{symbol.kind.upper()} {name} takes {symbol.params} argument"
                            f"{'s' if symbol.params != 1 else ''}, got {len(expr.arguments)}", "")
            return ANY
        spec = self.registry.functions.get(name)
        if name == "AXES" and spec is not None:
            return self.axes_call(expr, arg_types)
        if spec is None:
            self.report(expr.function, f"'{name}' is not a routine or a function", "")
            return ANY
        count = len(expr.arguments)
        if count < spec.min_args or (spec.max_args is not None and count > spec.max_args):
            expected = str(spec.min_args) if spec.max_args == spec.min_args else (
                f"at least {spec.min_args}" if spec.max_args is None else f"{spec.min_args} to {spec.max_args}")
            self.report(expr, f"{name} takes {expected} argument{'s' if expected != '1' else ''}, got {count}", "")
            return ANY
        for i, (argument, actual) in enumerate(zip(expr.arguments, arg_types)):
            param = spec.params[min(i, len(spec.params) - 1)] if argument.name is None else next(
                (p for p in spec.params if p.name == argument.name.id), None)
            if param is None:
                self.report(argument, f"{name} has no parameter '{argument.name.id}'", "")  # type: ignore[union-attr]
                continue
            if not accepts(param.types, actual):
                self.report(argument.value, f"argument '{param.name}' of {name} expects {describe_types(param.types)}, "
                            f"got {actual}", "")
        if name in _FRAME_KEEPING and arg_types and arg_types[0].kind == "pose":
            return arg_types[0]
        if name in ("POSE", "TRANSL"):
            return StaticType("pose", frame=frame)
        returns = spec.returns
        return number(returns) if isinstance(returns, Dimension) else StaticType(str(returns))

    def axes_call(self, expr: n.Call, arg_types: list[StaticType]) -> StaticType:
        """AXES(p, name = value, ...): a pose, then external-axis values by the cell's axis names (a length for a
        linear axis, an angle for a rotary one)."""
        positional = [(a, t) for a, t in zip(expr.arguments, arg_types) if a.name is None]
        if len(positional) != 1 or positional[0][1].kind not in ("pose", "any"):
            self.report(expr, "AXES takes a pose, then axis values by name: AXES(p, track = 200mm)", "")
            return ANY
        named = [(a, t) for a, t in zip(expr.arguments, arg_types) if a.name is not None]
        if not named:
            self.report(expr, "AXES needs at least one axis value, as in AXES(p, track = 200mm)", "")
        axes = self.external_axes
        for argument, actual in named:
            axis = argument.name.id  # type: ignore[union-attr]
            if axes is not None and axis not in axes:
                guess = suggest(axis, list(axes))
                known = f"the cell's axes are {', '.join(axes)}" if axes else "the cell has no external axes"
                self.report(argument.name, f"unknown external axis '{axis}'" + (f"; did you mean '{guess}'?" if guess else ""),
                            known + " (moving frames with 'axis:' in the world model, --world FILE)")
                continue
            wanted = (ANGLE,) if axes is not None and axes[axis] == "rotary" else (LENGTH,) if axes is not None else (LENGTH, ANGLE)
            if actual.kind == "number" and actual.dim not in (None, DIMENSIONLESS, *wanted):
                what = " or ".join(str(d) for d in wanted)
                self.report(argument.value, f"axis '{axis}' takes a{'n' if str(wanted[0])[0] in 'aeiou' else ''} {what}, got {actual}", "")
        return positional[0][1]

    def _Unary(self, expr: n.Unary, scope: Scope, frame: str) -> StaticType:
        operand = self.infer(expr.operand, scope, frame)
        return BOOL if expr.op == "NOT" else operand

    def _Binary(self, expr: n.Binary, scope: Scope, frame: str) -> StaticType:
        left = self.infer(expr.left, scope, frame)
        right = self.infer(expr.right, scope, frame)
        op = expr.op
        if op in ("AND", "OR"):
            return BOOL
        if left.kind == "pose" and op == "*":
            return left
        if left.kind != "number" or right.kind != "number" or left.dim is None or right.dim is None:
            return BOOL if op in ("=", "<>", "<", "<=", ">", ">=") else ANY
        if op in ("+", "-", "=", "<>", "<", "<=", ">", ">="):
            # A plain number meeting a quantity is in SI of the quantity's dimension (`HERE.y > 0`).
            if left.dim == DIMENSIONLESS:
                left = right
            elif right.dim == DIMENSIONLESS:
                right = left
            if left.dim != right.dim:
                verb = {"+": "add", "-": "subtract"}.get(op, "compare")
                joiner = "with" if verb == "compare" else ("from" if verb == "subtract" else "and")
                first, second = (right, left) if verb == "subtract" else (left, right)
                self.report(expr, f"cannot {verb} {first.dim} ({first.dim.symbol()}) {joiner} {second.dim} ({second.dim.symbol()})", "")  # type: ignore[union-attr]
                return ANY
            return left if op in ("+", "-") else BOOL
        if op == "*":
            return number(left.dim * right.dim)
        return number(left.dim / right.dim)

