"""The checker: every static rule of the language over one program, all errors of a file in one pass."""

from __future__ import annotations

from collections.abc import Iterable, Mapping

from orc_rpl.application.declarations import describe_types
from orc_rpl.application.registry import Registry, default_registry, suggest
from orc_rpl.checking.expressions import ExpressionTyper, accepts
from orc_rpl.checking.purity import ParameterUse, PurityProver
from orc_rpl.checking.symbols import (
    ANY, WORLD, Scope, StaticType, Symbol, assigned_names, builtin_scope, declarations, number,
)
from orc_rpl.errors import Diagnostic, Location
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.units import DIMENSIONLESS, TIME

_DECLARED_KIND = {"TOOL": "tool", "FRAME": "frame", "POS": "pos", "PATH": "path", "CONST": "const", "VAR": "var"}
_OUTPUTS = {"DigOut", "AnalogOut"}
_INPUTS = {"DigIn", "AnalogIn"}


class Checker:
    """Collects diagnostics for one program."""

    def __init__(self, path: str, registry: Registry) -> None:
        self.path = path
        self.registry = registry
        self.diagnostics: list[Diagnostic] = []
        self.types = ExpressionTyper(registry, self.report)
        self.installs: dict[str, str] = {}          #: installed name -> kind
        self.dimension_lines: dict[int, int] = {}   #: id of a variable's Symbol -> line that fixed its dimension
        self.routine_scopes: dict[str, tuple[n.Routine, Scope]] = {}
        self.function_returns: dict[str, list[tuple[StaticType, n.Node]]] = {}   #: FUNC -> what its RETURNs give
        self.parameter_uses: list[tuple[ParameterUse, n.Node]] = []   #: FUNCs the motion layer evaluates
        self.untils: list[tuple[n.Expression, Scope]] = []
        self.function_targets: list[tuple[n.Name, str, str]] = []     #: `TO f`/`ALONG f`: the frame and the role
        self._handlers: dict[type, object] = {}

    # ---- reporting
    def report(self, node: n.Node, message: str, hint: str = "") -> None:
        span = node.span
        location = Location(self.path, span.line or 1, span.column or 1, span.end_line, span.end_column)
        self.diagnostics.append(Diagnostic(location, message, hint))

    # ---- scopes
    def declare(self, scope: Scope, name_node: n.Name, kind: str, type_: StaticType, node: n.Node,
                params: int | None = None) -> None:
        existing = scope.symbols.get(name_node.id)
        if existing is not None and existing.node is not None and existing.kind != "assigned":
            line = existing.node.span.line
            self.report(name_node, f"'{name_node.id}' is already declared at line {line}")
            return
        if existing is not None and existing.kind == "predefined":
            self.report(name_node, f"'{name_node.id}' is a predefined name and cannot be declared again")
            return
        scope.symbols[name_node.id] = Symbol(name_node.id, kind, type_, node, params)

    def collect(self, body: n.Body, scope: Scope, top_level: bool) -> None:
        """Declare a scope's names before checking it, so routines may be called before they are written."""
        for stmt in declarations(body):
            if isinstance(stmt, n.Routine):
                if not top_level:
                    self.report(stmt.name, f"{stmt.kind} {stmt.name.id} must be declared at the top level, not inside a routine")
                    continue
                self.declare(scope, stmt.name, stmt.kind.lower(), StaticType("routine", detail=stmt.kind), stmt, len(stmt.params))
            elif isinstance(stmt, n.EnumDecl):
                self.declare(scope, stmt.name, "enum", StaticType("enum", detail=stmt.name.id), stmt)
                for member in stmt.members:
                    self.declare(scope, member, "enum_value", StaticType("enum", detail=stmt.name.id), stmt)
            elif isinstance(stmt, n.Install):
                kind_name = stmt.kind.id
                existing = scope.symbols.get(stmt.name.id)
                if existing is not None and existing.kind == "tool":
                    self.installs[stmt.name.id] = kind_name  # equipment mounted as an existing TOOL
                    continue
                self.installs[stmt.name.id] = kind_name
                self.declare(scope, stmt.name, "install", StaticType("installed", detail=kind_name), stmt)
            elif isinstance(stmt, n.Declaration):
                self.declare(scope, stmt.name, _DECLARED_KIND[stmt.kind], self.declared_type(stmt), stmt)
        for name, node in assigned_names(body):
            if scope.lookup(name) is None or (scope.routine is not None and name not in scope.symbols
                                              and (scope.parent is None or scope.parent.lookup(name) is None)):
                scope.symbols[name] = Symbol(name, "assigned", ANY, node)

    def declared_type(self, stmt: n.Declaration) -> StaticType:
        frame = stmt.frame.id if stmt.frame is not None else WORLD
        if stmt.kind == "TOOL":
            return StaticType("tool")
        if stmt.kind == "FRAME":
            return StaticType("frame", frame=frame)
        if stmt.kind in ("POS", "PATH"):
            value = stmt.value
            if isinstance(value, n.Call) and isinstance(value.function, n.Name) and value.function.id == "JOINTS":
                return StaticType("joints")
            return StaticType("pose" if stmt.kind == "POS" else "path", frame=frame)
        return ANY

    # ---- statements
    def check_body(self, body: n.Body, scope: Scope, frame: str) -> None:
        for stmt in body:
            self.check_statement(stmt, scope, frame)

    def check_statement(self, stmt: n.Statement, scope: Scope, frame: str) -> None:
        kind = type(stmt)
        handler = self._handlers.get(kind)
        if handler is None:
            handler = self._handlers[kind] = getattr(self, "_" + kind.__name__, _skip)
        handler(stmt, scope, frame)

    def infer(self, expr: n.Expression, scope: Scope, frame: str) -> StaticType:
        return self.types.infer(expr, scope, frame)

    def _Declaration(self, stmt: n.Declaration, scope: Scope, frame: str) -> None:
        value = self.infer(stmt.value, scope, frame)
        if stmt.frame is not None:
            self.check_frame_name(stmt.frame, scope)
        if stmt.kind in ("TOOL", "FRAME", "POS") and value.kind not in ("pose", "joints", "any"):
            self.report(stmt.value, f"{stmt.kind} {stmt.name.id} needs a pose, got {value}")
        if stmt.kind == "TOOL" and value.kind == "joints":
            self.report(stmt.value, f"TOOL {stmt.name.id} needs a pose, got a joints position")
        symbol = scope.symbols.get(stmt.name.id)
        if symbol is not None and symbol.kind in ("const", "var") and symbol.node is stmt:
            symbol.type = value

    def _Install(self, stmt: n.Install, scope: Scope, frame: str) -> None:
        kind = self.registry.install_kinds.get(stmt.kind.id)
        if kind is None:
            guess = suggest(stmt.kind.id, self.registry.install_kinds)
            self.report(stmt.kind, f"unknown INSTALL kind '{stmt.kind.id}'" + (f"; did you mean '{guess}'?" if guess else ""),
                        "known kinds: " + ", ".join(sorted(self.registry.install_kinds)))
            return
        seen: dict[str, n.With] = {}
        for attribute in stmt.attributes:
            spec = kind.attribute(attribute.name.id)
            value = self.infer(attribute.value, scope, frame)
            if spec is None:
                guess = suggest(attribute.name.id, [a.name for a in kind.attributes])
                self.report(attribute.name, f"{kind.name} does not accept attribute '{attribute.name.id}'"
                            + (f"; did you mean '{guess}'?" if guess else ""),
                            "accepted: " + ", ".join(a.name for a in kind.attributes))
                continue
            self.check_duplicate_attribute(seen, spec.name, attribute)
            if not accepts(spec.types, value):
                self.report(attribute.value, f"attribute {spec.name} of {kind.name} expects {describe_types(spec.types)}, got {value}")
            elif spec.literal_check is not None and isinstance(attribute.value, n.String):
                problem = spec.literal_check(attribute.value.value)
                if problem is not None:
                    self.report(attribute.value, f"attribute {spec.name} of {kind.name}: {problem}")

    def check_duplicate_attribute(self, seen: dict[str, n.With], canonical: str, attribute: n.With) -> None:
        if canonical in seen:
            self.report(attribute.name, f"attribute {canonical} is given twice (first at line {seen[canonical].span.line})")
        seen[canonical] = attribute

    def _Motion(self, stmt: n.Motion, scope: Scope, frame: str) -> None:
        spec = self.registry.motions.get(stmt.keyword)
        if spec is None:
            guess = suggest(stmt.keyword, self.registry.motions)
            self.report(stmt, f"unknown motion keyword '{stmt.keyword}'" + (f"; did you mean '{guess}'?" if guess else ""),
                        "" if guess else "registered: " + ", ".join(sorted(self.registry.motions)))
        self.check_tool(stmt, scope, frame)
        counts = {"TO": 0, "ALONG": 0, "VIA": 0}
        seen: dict[str, n.With] = {}
        for clause in stmt.clauses:
            if isinstance(clause, n.To):
                counts["TO"] += 1
                self.check_target(clause.target, scope, frame, "target")
                if counts["TO"] > 1:
                    self.report(clause, "a motion has one TO target")
            elif isinstance(clause, n.Along):
                counts["ALONG"] += 1
                self.check_target(clause.path, scope, frame, "path")
            elif isinstance(clause, n.Via):
                counts["VIA"] += 1
                for point in clause.points:
                    self.check_target(point, scope, frame, "via point")
            elif isinstance(clause, n.Until):
                self.infer(clause.condition, scope, frame)
                self.untils.append((clause.condition, scope))
            elif isinstance(clause, n.With):
                self.check_attribute(stmt, spec, clause, scope, frame, seen)
        if spec is None:
            return
        given = [k for k in ("TO", "ALONG") if counts[k]]
        if not given:
            wanted = " or ".join(f"{k} a {'target' if k == 'TO' else 'path'}" for k in spec.targets)
            self.report(stmt, f"{stmt.keyword} needs {wanted}")
        elif len(given) > 1:
            self.report(stmt, f"{stmt.keyword} takes either TO or ALONG, not both")
        elif given[0] not in spec.targets:
            self.report(stmt, f"{stmt.keyword} does not move ALONG a path; use TO")
        if spec.needs_via and counts["VIA"] == 0:
            self.report(stmt, f"{stmt.keyword} needs a VIA point (the circle passes through it)")
        target = stmt.target if stmt.target is not None else stmt.path
        if isinstance(target, n.Name) and "TIME" not in seen:
            symbol = scope.lookup(target.id)
            routine = symbol.node if symbol is not None and symbol.kind == "func" else None
            if isinstance(routine, n.Routine) and [p.id for p in routine.params] == ["t"]:
                self.report(target, f"FUNC {target.id}(t) is a function of time: the motion needs its duration",
                            "add WITH TIME = 5s (t runs from 0 to that duration)")
        for required in spec.requires:
            if self.installs.get(stmt.tool.id) != required:
                self.report(stmt.tool, f"{stmt.keyword} needs a {required} installed on tool '{stmt.tool.id}'",
                            f"add `INSTALL {stmt.tool.id} AS {required} WITH ...`")

    def check_tool(self, stmt: n.Motion, scope: Scope, frame: str) -> None:
        symbol = scope.lookup(stmt.tool.id)
        if symbol is None:
            guess = suggest(stmt.tool.id, [*self.names_of_kind(scope, "tool"), "ARM"])
            self.report(stmt.tool, f"unknown tool '{stmt.tool.id}'" + (f"; did you mean '{guess}'?" if guess else ""),
                        "declare it with TOOL name = POSE(...), or move the bare flange with ARM")
        elif symbol.kind not in ("tool", "install", "param", "var", "assigned") and stmt.tool.id != "ARM":
            self.report(stmt.tool, f"'{stmt.tool.id}' is not a tool")

    def check_target(self, expr: n.Expression, scope: Scope, frame: str, role: str) -> None:
        """The FRAME-context rule: inside `FRAME f` a target must be relative to f; outside, to world."""
        if role in ("target", "path") and isinstance(expr, n.Name) and self.function_target(expr, scope, frame, role):
            return
        target = self.infer(expr, scope, frame)
        if target.kind in ("pose", "path") and target.frame is not None and target.frame != frame:
            where = f"inside FRAME {frame}" if frame != WORLD else "outside every FRAME block (relative to world)"
            fix = f"FRAME {target.frame}" if target.frame != WORLD else "no FRAME block"
            self.report(expr, f"{role} '{_describe(expr)}' is relative to {target.frame}, but this motion is {where}",
                        f"move the statement into {fix}, or declare the position IN {frame}")
        elif target.kind not in ("pose", "joints", "path", "list", "any"):
            self.report(expr, f"the {role} must be a position, got {target}")

    def function_target(self, expr: n.Name, scope: Scope, frame: str, role: str) -> bool:
        """`LMOVE ARM TO wave` or `ALONG wave` with `FUNC wave(s)`: a motion in function space (frames checked when all
        RETURNs are known); `role` is "target" or "path"."""
        symbol = scope.lookup(expr.id)
        if symbol is None or symbol.kind != "func":
            return False
        if symbol.params != 1:
            self.report(expr, f"FUNC {expr.id} given as a {role} must take one parameter (s, 0..1), not {symbol.params}")
            return True
        self.function_targets.append((expr, frame, role))
        self.parameter_uses.append((ParameterUse(expr.id, f"the {role}", expr.span.line), expr))
        return True

    def check_attribute(self, stmt: n.Motion, spec, clause: n.With, scope: Scope, frame: str, seen: dict) -> None:  # type: ignore[no-untyped-def]
        name = clause.name.id
        value = self.infer(clause.value, scope, frame)
        if spec is None:
            return
        if (isinstance(clause.value, n.Call) and isinstance(clause.value.function, n.Name)
                and clause.value.function.id in spec.output_functions):
            for argument in clause.value.arguments:  # an output binding: `WITH Id = IDENT(classify, parts)`
                if isinstance(argument.value, n.Name) and (scope.lookup(argument.value.id) or Symbol("", "")).kind == "func":
                    use = ParameterUse(argument.value.id, f"the {clause.value.function.id} classifier", stmt.span.line)
                    self.parameter_uses.append((use, argument.value))
            return
        attribute = spec.attribute(name)
        if attribute is None:
            guess = suggest(name, spec.attribute_names)
            elsewhere = sorted(k for k, other in self.registry.motions.items() if other.attribute(name) is not None)
            hint = "accepted: " + ", ".join(a.name for a in spec.attributes)
            if elsewhere and not guess:
                hint = f"{name} is an attribute of {', '.join(elsewhere)}; {hint}"
            self.report(clause.name, f"{stmt.keyword} does not accept attribute '{name}'" + (f"; did you mean '{guess}'?" if guess else ""),
                        hint)
            return
        self.check_duplicate_attribute(seen, attribute.name, clause)
        if isinstance(clause.value, n.Name):
            symbol = scope.lookup(clause.value.id)
            if symbol is not None and symbol.kind == "func":
                if not attribute.function_ok:
                    self.report(clause.value, f"attribute {attribute.name} cannot be a function")
                else:
                    self.parameter_uses.append((ParameterUse(clause.value.id, f"attribute {attribute.name}", stmt.span.line),
                                                clause.value))
                return
        if not accepts(attribute.types, value):
            self.report(clause.value, f"attribute {attribute.name} of {stmt.keyword} expects {describe_types(attribute.types)}, got {value}")
        elif attribute.literal_check is not None and isinstance(clause.value, n.String):
            problem = attribute.literal_check(clause.value.value)
            if problem is not None:
                self.report(clause.value, f"attribute {attribute.name} of {stmt.keyword}: {problem}")

    def _Assign(self, stmt: n.Assign, scope: Scope, frame: str) -> None:
        value = self.infer(stmt.value, scope, frame)
        target = stmt.target
        if isinstance(target, n.Name):
            self.track_dimension(target, stmt.value, value, scope)
        root = target
        while isinstance(root, (n.Field, n.Index)):
            root = root.value
        if isinstance(root, n.Name):
            symbol = scope.lookup(root.id)
            if symbol is not None and symbol.kind == "const":
                self.report(root, f"'{root.id}' is a CONST and cannot be assigned")
            elif root.id in _INPUTS:
                self.report(root, f"{root.id} is an input and cannot be assigned", "write to DigOut or AnalogOut")
            elif symbol is not None and symbol.kind in ("unit", "function", "proc", "func", "enum", "enum_value"):
                self.report(root, f"'{root.id}' is a {symbol.kind.replace('_', ' ')} and cannot be assigned")
        if not isinstance(target, n.Name):
            self.infer(target, scope, frame)

    def track_dimension(self, target: n.Name, expr: n.Expression, value: StaticType, scope: Scope) -> None:
        """A variable takes the dimension of the quantities assigned to it; a second dimension is an error.

        Plain numbers fit any dimension (they are SI of the dimension the context needs), so `x = 0` then
        `x = x + 1mm` is fine. The check follows the file order, which is enough to catch `a = 2s` then
        `c = a + 30mm` before the program runs.
        """
        symbol = scope.lookup(target.id)
        if symbol is None or symbol.kind not in ("assigned", "var"):
            return
        old = symbol.type
        if value.kind != "number" or value.dim is None:
            if old.kind == "number" and value.kind != "any":
                symbol.type = ANY  # a variable that changes kind: the checker cannot tell any more
            return
        if old.kind == "number" and old.dim not in (None, DIMENSIONLESS) and value.dim not in (DIMENSIONLESS, old.dim):
            line = self.dimension_lines.get(id(symbol), "?")
            self.report(expr, f"'{target.id}' holds {old} (since line {line}); it cannot be given {value}",
                        "use another variable for a value of another dimension")
            return
        if old.kind in ("number", "any") and value.dim != DIMENSIONLESS or old.kind == "any":
            if old.dim != value.dim:
                self.dimension_lines[id(symbol)] = expr.span.line
            symbol.type = value

    def _CallStatement(self, stmt: n.CallStatement, scope: Scope, frame: str) -> None:
        call = stmt.call
        if isinstance(call, n.Name):
            symbol = scope.lookup(call.id)
            if symbol is None:
                guess = suggest(call.id, scope.visible_names())
                self.report(call, f"undefined routine '{call.id}'" + (f"; did you mean '{guess}'?" if guess else ""))
            elif symbol.kind in ("proc", "func") and symbol.params:
                self.report(call, f"{symbol.kind.upper()} {call.id} takes {symbol.params} argument"
                            f"{'s' if symbol.params != 1 else ''}, got 0")
            elif symbol.kind not in ("proc", "func", "function"):
                self.report(call, f"'{call.id}' is not a routine and cannot be called")
            return
        result = self.infer(call, scope, frame)
        if isinstance(call, n.Field) and result.kind not in ("command", "any"):
            self.report(call, f"'{_describe(call)}' is a value, not a command; assign it or test it")

    def _Wait(self, stmt: n.Wait, scope: Scope, frame: str) -> None:
        self.expect_time(stmt.duration, scope, frame, "WAIT")

    def _WaitUntil(self, stmt: n.WaitUntil, scope: Scope, frame: str) -> None:
        self.infer(stmt.condition, scope, frame)
        if stmt.timeout is not None:
            self.expect_time(stmt.timeout, scope, frame, "TIMEOUT")

    def expect_time(self, expr: n.Expression, scope: Scope, frame: str, what: str) -> None:
        value = self.infer(expr, scope, frame)
        if value.kind == "number" and value.dim not in (None, TIME):
            self.report(expr, f"{what} expects a time, got {value}", "write a unit: 0.5s or 500ms")
        elif value.kind not in ("number", "any"):
            self.report(expr, f"{what} expects a time, got {value}")

    def _Print(self, stmt: n.Print, scope: Scope, frame: str) -> None:
        for value in stmt.values:
            self.infer(value, scope, frame)

    def _Return(self, stmt: n.Return, scope: Scope, frame: str) -> None:
        if stmt.value is not None:
            if scope.routine is None or scope.routine.kind != "FUNC":
                self.report(stmt, "RETURN with a value outside a FUNC", "a PROC or the main program returns without a value")
            value = self.infer(stmt.value, scope, frame)
            if scope.routine is not None and scope.routine.kind == "FUNC":
                self.function_returns.setdefault(scope.routine.name.id, []).append((value, stmt.value))

    def _If(self, stmt: n.If, scope: Scope, frame: str) -> None:
        for branch in stmt.branches:
            self.infer(branch.condition, scope, frame)
            self.check_body(branch.body, scope, frame)
        if stmt.else_body is not None:
            self.check_body(stmt.else_body, scope, frame)

    def _While(self, stmt: n.While, scope: Scope, frame: str) -> None:
        self.infer(stmt.condition, scope, frame)
        self.check_body(stmt.body, scope, frame)

    def _For(self, stmt: n.For, scope: Scope, frame: str) -> None:
        bounds = [self.infer(e, scope, frame) for e in (stmt.start, stmt.stop, stmt.step) if e is not None]
        dims = {b.dim for b in bounds if b.kind == "number" and b.dim is not None}
        if len(dims) > 1:
            self.report(stmt.start, "FOR bounds and step must have the same dimension: " + ", ".join(str(d) for d in dims))
        self.check_body(stmt.body, scope, frame)

    def _Case(self, stmt: n.Case, scope: Scope, frame: str) -> None:
        self.infer(stmt.subject, scope, frame)
        self.check_body(stmt.leading, scope, frame)
        for arm in (*stmt.arms, *([stmt.else_arm] if stmt.else_arm else [])):
            for label in arm.labels:
                self.infer(label, scope, frame)
            self.check_body(tuple(s for s in (arm.inline,) if s is not None) + arm.body, scope, frame)

    def _FrameBlock(self, stmt: n.FrameBlock, scope: Scope, frame: str) -> None:
        self.check_frame_name(stmt.frame, scope)
        self.check_body(stmt.body, scope, stmt.frame.id)

    def check_frame_name(self, name: n.Name, scope: Scope) -> None:
        """A name used as an on-line frame (`IN f`, `FRAME f` block) must be a declared FRAME or world."""
        symbol = scope.lookup(name.id)
        if name.id != WORLD and (symbol is None or symbol.kind != "frame"):
            guess = suggest(name.id, self.names_of_kind(scope, "frame"))
            self.report(name, f"unknown frame '{name.id}'" + (f"; did you mean '{guess}'?" if guess else ""),
                        "declare it with FRAME name = POSE(...)")

    @staticmethod
    def names_of_kind(scope: Scope, kind: str) -> list[str]:
        """Visible names declared as `kind` (frame, tool, ...), for did-you-mean."""
        return [name for name in scope.visible_names() if (scope.lookup(name) or Symbol(name, "")).kind == kind]

    def _Try(self, stmt: n.Try, scope: Scope, frame: str) -> None:
        self.check_body(stmt.body, scope, frame)
        for handler in stmt.handlers:
            self.check_body(tuple(s for s in (handler.inline,) if s is not None) + handler.body, scope, frame)

    def _Routine(self, stmt: n.Routine, scope: Scope, frame: str) -> None:
        local = Scope(parent=scope, routine=stmt)
        for param in stmt.params:
            if param.id in local.symbols:
                self.report(param, f"parameter '{param.id}' is given twice")
            local.symbols[param.id] = Symbol(param.id, "param", ANY, param)
        self.collect(stmt.body, local, top_level=False)
        self.routine_scopes.setdefault(stmt.name.id, (stmt, local))
        self.check_body(stmt.body, local, WORLD)

    # ---- what needs the whole program: parameter functions
    def return_with_typed_parameter(self, function: str, value: n.Expression) -> StaticType:
        """What a function target's RETURN gives when its one parameter is the path coordinate s (a number) or the
        time t; diagnostics of this second look are dropped (the body was checked once already)."""
        routine, local = self.routine_scopes[function]
        param = routine.params[0].id
        typed = Scope(parent=local, routine=routine)
        typed.symbols[param] = Symbol(param, "param", number(TIME if param == "t" else DIMENSIONLESS), routine.params[0])
        reported = len(self.diagnostics)
        try:
            return self.infer(value, typed, WORLD)
        finally:
            del self.diagnostics[reported:]

    def finish(self, scope: Scope) -> None:
        """Checks that need every routine: FUNC targets give poses of the motion's frame; parameter FUNCs are pure."""
        for expr, frame, role in self.function_targets:
            for value, node in self.function_returns.get(expr.id, []):
                if value.kind == "any":  # `RETURN 2 * s`: typed again with s a number (t a time), as the motion calls it
                    value = self.return_with_typed_parameter(expr.id, node)
                if value.kind == "pose" and value.frame is not None and value.frame != frame:
                    where = f"inside FRAME {frame}" if frame != WORLD else "outside every FRAME block (relative to world)"
                    self.report(expr, f"FUNC {expr.id} gives poses relative to {value.frame} (line {node.span.line}), "
                                f"but this motion is {where}", f"return poses relative to {frame}")
                    break
                if value.kind not in ("pose", "any"):
                    self.report(expr, f"FUNC {expr.id} given as a {role} must give poses; line {node.span.line} gives {value}")
                    break
        prover = PurityProver(self.registry, scope, self.routine_scopes, self.installs)
        reported: set[str] = set()
        for use, node in self.parameter_uses:
            effect = prover.side_effect(use.function)
            if effect is None or use.function in reported:
                continue
            reported.add(use.function)
            self.report(effect.node, f"FUNC {use.function} is used as {use.role} at line {use.line}, so it must be "
                        f"free of side effects, but it {effect.reason}",
                        "the planner evaluates it many times, at moments the program does not choose")
        for condition, where in self.untils:
            effect = prover.expression_effect(condition, where)
            if effect is not None:
                self.report(effect.node, f"an UNTIL condition must be free of side effects, but this one {effect.reason}",
                            "the motion cycle evaluates it every 4 ms")


def _skip(stmt: n.Statement, scope: Scope, frame: str) -> None:
    """Statements with nothing to check (comments, blank lines, STOP)."""


def _describe(expr: n.Expression) -> str:
    from orc_rpl.syntax.printer import expression

    return expression(expr)


def check_program(program: n.Program, path: str = "<input>", registry: Registry | None = None,
                  world_attributes: Mapping[str, Mapping[str, object]] | None = None,
                  moving_frames: Mapping[str, str] | None = None) -> list[Diagnostic]:
    """Every static error of a program, in file order (empty when the program is clean).

    `world_attributes` (object -> soft and spatial attributes) are the program's world: `pallet.next_row` is checked
    against it; without it such a field is an error. `moving_frames` (name -> linear, rotary or conveyor) are the
    cell's moving frames: frames a program may name (`FRAME part = POSE(...) IN turn`) and, but for conveyors, the
    external axes AXES(p, ...) may give values to; None when the cell is not known (axis names are not checked).
    """
    registry = registry or default_registry()
    checker = Checker(path, registry)
    checker.types.world_attributes = world_attributes or {}
    scope = Scope(parent=_cell_scope(checker, registry, moving_frames))
    checker.collect(program.body, scope, top_level=True)
    checker.check_body(program.body, scope, WORLD)
    checker.finish(scope)
    return sorted(checker.diagnostics, key=lambda d: (d.location.line, d.location.column))


def _cell_scope(checker: Checker, registry: Registry, moving_frames: Mapping[str, str] | None) -> Scope:
    """The built-in names, and the cell's moving frames as frames (their axes the ones AXES may move)."""
    builtins = builtin_scope(list(registry.functions))
    if moving_frames is not None:
        checker.types.external_axes = {k: v for k, v in moving_frames.items() if v != "conveyor"}
        for name in moving_frames:
            builtins.symbols[name] = Symbol(name, "frame", StaticType("frame", frame=WORLD))
    return builtins


def check_in_context(program: n.Program, statement: n.Statement, routine: str | None = None, frame: str = WORLD,
                     path: str = "<typed>", registry: Registry | None = None,
                     live_names: Iterable[str] = (), moving_frames: Mapping[str, str] | None = None) -> list[Diagnostic]:
    """The static errors of one statement as if it stood in `program`: inside routine `routine` (None: the main
    program) and FRAME block `frame`; `live_names` are globals that exist already (earlier typed assignments),
    `moving_frames` the cell's (see check_program). The program's own errors are not reported (the pendant's
    typed statements)."""
    registry = registry or default_registry()
    checker = Checker(path, registry)
    scope = Scope(parent=_cell_scope(checker, registry, moving_frames))
    checker.collect(program.body, scope, top_level=True)
    for name in live_names:
        if scope.lookup(name) is None:
            scope.symbols[name] = Symbol(name, "assigned", ANY, None)
    owner = next((s for s in program.body if isinstance(s, n.Routine) and s.name.id == routine), None)
    if owner is not None:
        scope = Scope(parent=scope, routine=owner)
        for param in owner.params:
            scope.symbols[param.id] = Symbol(param.id, "param", ANY, param)
        checker.collect(owner.body, scope, top_level=False)
    checker.collect((statement,), scope, top_level=owner is None)
    checker.diagnostics.clear()
    checker.check_statement(statement, scope, frame)
    return sorted(checker.diagnostics, key=lambda d: (d.location.line, d.location.column))
