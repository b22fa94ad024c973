"""Pure parameter functions: a FUNC the planner or the controller evaluates (target, attribute, UNTIL, IDENT) has no side effects."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

from orc_rpl.application.registry import Registry
from orc_rpl.checking.symbols import Scope
from orc_rpl.syntax import nodes as n

_OUTPUTS = ("DigOut", "AnalogOut")


@dataclass(frozen=True, slots=True)
class ParameterUse:
    """A FUNC named where the motion layer evaluates it: `LMOVE ARM TO wave`, `WITH FORCE = ramp`, `UNTIL seen()`."""

    function: str        #: the FUNC's name
    role: str            #: "the target", "attribute FORCE", "the UNTIL condition", "the IDENT classifier"
    line: int            #: the motion statement's line


@dataclass(frozen=True, slots=True)
class SideEffect:
    """Why a routine is not pure, and the statement or expression that makes it so."""

    node: n.Node
    reason: str          #: "assigns the global 'count'", "calls Helper, which moves the robot (LMOVE)"


class PurityProver:
    """Decides, once per routine, whether calling it can change anything outside its own call."""

    def __init__(self, registry: Registry, globals_: Scope, routines: dict[str, tuple[n.Routine, Scope]],
                 installs: dict[str, str]) -> None:
        self.registry = registry
        self.globals = globals_
        self.routines = routines            #: name -> (declaration, its local scope as the checker built it)
        self.installs = installs            #: installed name -> kind
        self._known: dict[str, SideEffect | None] = {}

    def side_effect(self, name: str) -> SideEffect | None:
        """The first side effect of routine `name` (following the routines it calls), or None when it is pure."""
        if name in self._known:
            return self._known[name]
        self._known[name] = None            # a recursive call adds nothing new: assume pure while proving
        found = self._routine_effect(*self.routines[name]) if name in self.routines else None
        self._known[name] = found
        return found

    def expression_effect(self, expr: n.Expression, scope: Scope) -> SideEffect | None:
        """The first side effect of evaluating `expr` (an UNTIL condition: the calls it makes)."""
        return next(self._expression_effects(expr, scope), None)

    def _routine_effect(self, routine: n.Routine, local: Scope) -> SideEffect | None:
        for stmt in routine.body:
            for node in _statements(stmt):
                found = self._statement_effect(node, local)
                if found is not None:
                    return found
        return None

    def _statement_effect(self, stmt: n.Statement, local: Scope) -> SideEffect | None:
        if isinstance(stmt, n.Motion):
            return SideEffect(stmt, f"moves the robot ({stmt.keyword})")
        if isinstance(stmt, (n.Wait, n.WaitUntil)):
            return SideEffect(stmt, "waits")
        if isinstance(stmt, n.Print):
            return SideEffect(stmt, "prints")
        if isinstance(stmt, n.Stop):
            return SideEffect(stmt, "stops the program")
        if isinstance(stmt, n.Install):
            return SideEffect(stmt, f"installs {stmt.name.id}")
        if isinstance(stmt, n.Assign):
            root = stmt.target
            while isinstance(root, (n.Field, n.Index)):
                root = root.value
            if isinstance(root, n.Name):
                if root.id in _OUTPUTS:
                    return SideEffect(stmt, f"writes the output {root.id}")
                if root.id not in local.symbols and self.globals.lookup(root.id) is not None:
                    return SideEffect(stmt, f"assigns the global '{root.id}'")
        if isinstance(stmt, n.CallStatement) and isinstance(stmt.call, n.Field):
            owner = stmt.call.value
            if isinstance(owner, n.Name) and owner.id in self.installs:
                kind = self.registry.install_kinds.get(self.installs[owner.id])
                method = kind.method(stmt.call.name.id) if kind is not None else None
                if method is None or method.returns is None:
                    return SideEffect(stmt, f"operates {owner.id} ({owner.id}.{stmt.call.name.id})")
        for expr in _expressions(stmt):
            found = next(self._expression_effects(expr, local), None)
            if found is not None:
                return SideEffect(stmt, found.reason)
        return None

    def _expression_effects(self, expr: n.Expression, scope: Scope) -> Iterator[SideEffect]:
        for name in _called_names(expr):
            symbol = scope.lookup(name.id)
            if symbol is None:
                continue
            if symbol.kind in ("proc", "func"):
                inner = self.side_effect(name.id)
                if inner is not None:
                    line = inner.node.span.line
                    yield SideEffect(name, f"calls {name.id}, which {inner.reason} (line {line})")
            elif symbol.kind == "function":
                spec = self.registry.functions.get(name.id)
                if spec is not None and not spec.pure:
                    yield SideEffect(name, f"calls {name.id}, which moves the robot")


def _statements(stmt: n.Statement) -> Iterator[n.Statement]:
    """A statement and every statement nested in it (routines are declared at the top level only)."""
    yield stmt
    for child in stmt.children():
        if isinstance(child, n.Statement):
            yield from _statements(child)
        elif isinstance(child, (n.Branch, n.CaseArm, n.Handler)):
            for inner in child.children():
                if isinstance(inner, n.Statement):
                    yield from _statements(inner)


def _expressions(stmt: n.Statement) -> Iterator[n.Expression]:
    """The expressions a statement evaluates itself (not those of nested statements)."""
    for child in stmt.children():
        if isinstance(child, n.Expression):
            yield child
        elif isinstance(child, n.Branch):
            yield child.condition


def _called_names(expr: n.Expression) -> Iterator[n.Name]:
    """Names in an expression that may call a routine: call heads and bare names (a FUNC without parameters)."""
    stack: list[n.Node] = [expr]
    while stack:
        node = stack.pop()
        if isinstance(node, n.Name):
            yield node
        elif isinstance(node, n.Field):
            stack.append(node.value)             # the field's own name is not a call
        elif isinstance(node, n.Argument):
            stack.append(node.value)             # nor is a keyword argument's name
        else:
            stack.extend(node.children())
