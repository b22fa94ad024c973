"""Statements of docs/language.md section 6 compiled into closures: assignment, PRINT, control flow, TRY, WAIT, calls."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any

from orc_rpl.executive import operators as ops
from orc_rpl.executive.blocks import Block, Compiled, Locals, make_block
from orc_rpl.executive.control import ControlFlow
from orc_rpl.executive.declarations import DeclarationCompiler
from orc_rpl.executive.expressions import ExpressionCompiler, invoke_method, merge_named, set_robot_setting
from orc_rpl.executive.machine import TICK, Machine
from orc_rpl.executive.motions import MotionCompiler
from orc_rpl.executive.scope import ProgramScopes, Scope
from orc_rpl.executive.signals import ReturnSignal, RunError, StopSignal
from orc_rpl.executive.values import IO_BANKS, Installed, IOBank, RobotSignals, format_value, type_name
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.limits import MAX_DURATION_S
from orc_rpl.syntax.units import TIME, Quantity

#: Names whose value the cell changes: a WHILE polling them lets one motion cycle pass per iteration.
class StatementCompiler(ControlFlow):
    """Compiles statements and blocks for one Machine."""

    def __init__(self, machine: Machine, scopes: ProgramScopes) -> None:
        self.m = machine
        self.scopes = scopes
        self.exprs = ExpressionCompiler(machine, scopes)
        self.motions = MotionCompiler(machine, scopes, self.exprs)
        self.declarations = DeclarationCompiler(machine, scopes, self.exprs, self)

    # -- blocks ----------------------------------------------------------------------------

    def block(self, body: n.Body, scope: Scope) -> Block:
        statements = [stmt for stmt in body if not isinstance(stmt, (n.Comment, n.Blank, n.Routine))]
        items = []
        for i, stmt in enumerate(statements):
            following = statements[i + 1] if i + 1 < len(statements) else None
            if isinstance(stmt, n.Motion) and isinstance(following, n.Motion):  # planned while this one runs
                try:
                    items.append(Compiled(stmt, None, self.motions.compile(stmt, scope, following)))
                    continue
                except RunError:  # reported when run, as statement() does
                    pass
            items.append(self.statement(stmt, scope))
        return make_block(self.m, items)

    def _blank(self, stmt: n.Statement, scope: Scope) -> tuple[Any, Any]:
        """A blank or comment line run on its own (the pendant's :exec on it) does nothing."""
        return (lambda L: None), None

    _comment = _blank

    def statement(self, stmt: n.Statement, scope: Scope) -> Compiled:
        method = getattr(self, "_" + type(stmt).__name__.lower(), None)
        if method is None:
            method = getattr(self.declarations, "_" + type(stmt).__name__.lower(), None)
        if method is None:
            def unsupported(L: Locals) -> None:
                raise RunError(f"internal error (a bug in orc_rpl, please report it): cannot run {type(stmt).__name__}")
            return Compiled(stmt, unsupported, None)
        try:
            fast, gen = method(stmt, scope)
        except RunError as error:  # found while compiling (the checker normally refuses it): report it when run
            def fail(L: Locals, error: RunError = error) -> None:
                raise error
            return Compiled(stmt, fail, None)
        return Compiled(stmt, fast, gen)

    def store(self, name: str, scope: Scope) -> Callable[[Locals, Any], None]:
        """A closure assigning `name` in the right scope; a CONST refuses."""
        if scope.is_local(name):
            def set_local(L: Locals, value: Any) -> None:
                L[name] = value
            return set_local
        G, consts = self.m.globals, self.m.consts

        def set_global(L: Locals, value: Any) -> None:
            if name in consts:
                raise RunError(f"'{name}' is a CONST: it cannot be assigned")
            G[name] = value
        return set_global

    # -- simple statements --------------------------------------------------------------------

    def _assign(self, stmt: n.Assign, scope: Scope) -> tuple[Any, Any]:
        value = self.exprs.compile(stmt.value, scope)
        setter = self.setter(stmt.target, scope)
        if _is_io(stmt.target, scope, self.scopes):
            m = self.m

            def write_io(L: Locals) -> Iterator[object]:
                yield from m.sync()  # an output changes when the robot has arrived
                setter(L, value(L))
            return None, write_io
        if isinstance(stmt.target, n.Name):
            return _assign_direct(self.store(stmt.target.id, scope), value), None
        return (lambda L: setter(L, value(L))), None

    def setter(self, target: n.Expression, scope: Scope) -> Callable[[Locals, Any], None]:
        """Assignment into a name, a list element, a field or an IO channel (values are copied, never shared)."""
        if isinstance(target, n.Name):
            return self.store(target.id, scope)
        if isinstance(target, n.Index):
            get_base, set_base = self.exprs.compile(target.value, scope), self.setter(target.value, scope)
            index, m = self.exprs.compile(target.index, scope), self.m

            def set_item(L: Locals, value: Any) -> None:
                base, i = get_base(L), index(L)
                if type(base) is IOBank:
                    m.write_io(base, i, value)
                elif type(base) is tuple:
                    k = ops.list_index(base, i)
                    set_base(L, base[:k] + (value,) + base[k + 1:])
                else:
                    raise RunError(f"cannot assign an element of {type_name(base)}")
            return set_item
        if isinstance(target, n.Field):
            get_base, set_base = self.exprs.compile(target.value, scope), self.setter(target.value, scope)
            name = target.name.id
            m = self.m

            def set_field(L: Locals, value: Any) -> None:
                base = get_base(L)
                if type(base) is RobotSignals:
                    set_robot_setting(m, name, value)
                    return
                if type(base) is Installed:
                    raise RunError(f"{base.name}.{name} cannot be assigned")
                set_base(L, ops.set_field(base, name, value))
            return set_field
        raise RunError("this cannot be assigned")

    def _motion(self, stmt: n.Motion, scope: Scope) -> tuple[Any, Any]:
        return None, self.motions.compile(stmt, scope)

    def _print(self, stmt: n.Print, scope: Scope) -> tuple[Any, Any]:
        values = [self.exprs.compile(v, scope) for v in stmt.values]
        m = self.m

        def print_(L: Locals) -> None:
            line = " ".join([format_value(f(L)) for f in values])
            m.prints.append(line)
            m.output(line)
        return print_, None

    def _raise(self, stmt: n.Raise, scope: Scope) -> tuple[Any, Any]:
        name = stmt.name.id

        def raise_(L: Locals) -> None:
            raise RunError(f"exception {name} was raised and not caught", name=name)
        return raise_, None

    def _return(self, stmt: n.Return, scope: Scope) -> tuple[Any, Any]:
        if stmt.value is None:
            def return_none(L: Locals) -> None:
                raise ReturnSignal(None)
            return return_none, None
        value = self.exprs.compile(stmt.value, scope)

        def return_(L: Locals) -> None:
            raise ReturnSignal(value(L))
        return return_, None

    def _stop(self, stmt: n.Stop, scope: Scope) -> tuple[Any, Any]:
        m, span = self.m, stmt.span

        def stop(L: Locals) -> Iterator[object]:
            m.robot.stop()
            while m.robot.pending() > 0:
                m.robot.tick()
                yield TICK
            raise StopSignal(span)
        return None, stop

    def _wait(self, stmt: n.Wait, scope: Scope) -> tuple[Any, Any]:
        duration, m = self.exprs.compile(stmt.duration, scope), self.m

        def wait(L: Locals) -> Iterator[object]:
            value = duration(L)
            seconds = _seconds(value, "WAIT")
            yield from m.sync()
            robot = m.robot
            end = robot.time_s() + seconds - 1e-9
            while robot.time_s() < end:
                robot.tick()
                yield TICK
        return None, wait

    def _waituntil(self, stmt: n.WaitUntil, scope: Scope) -> tuple[Any, Any]:
        condition, m = self.exprs.condition(stmt.condition, scope), self.m
        timeout = self.exprs.compile(stmt.timeout, scope) if stmt.timeout is not None else None

        def wait_until(L: Locals) -> Iterator[object]:
            limit = _seconds(timeout(L), "TIMEOUT") if timeout is not None else m.options.idle_wait_limit_s
            yield from m.sync()
            robot = m.robot
            end = None if limit is None else robot.time_s() + limit - 1e-9
            while not condition(L):
                if end is not None and robot.time_s() >= end:
                    if timeout is not None:
                        raise RunError(f"Timeout: the condition did not become true within {format_value(timeout(L))}",
                                       name="Timeout")
                    raise RunError(f"WAIT UNTIL waited {limit:g} s of robot time and the condition never became true")
                robot.tick()
                yield TICK
        return None, wait_until

    def _callstatement(self, stmt: n.CallStatement, scope: Scope) -> tuple[Any, Any]:
        call = stmt.call
        function = call.function if isinstance(call, n.Call) else call
        arguments = call.arguments if isinstance(call, n.Call) else ()
        m = self.m
        if isinstance(function, n.Name) and function.id in self.scopes.routines and not scope.is_local(function.id):
            return None, self._routine_call(function.id, arguments, scope, stmt.span)
        if isinstance(function, n.Field):
            target = self.exprs.compile(function.value, scope)
            args = [self.exprs.compile(a.value, scope) for a in arguments]
            method = function.name.id

            def method_call(L: Locals) -> Iterator[object]:
                obj = target(L)
                if type(obj) is not Installed:
                    raise RunError(f"{type_name(obj)} has no method '{method}'")
                yield from m.sync()  # equipment acts where the robot has arrived
                invoke_method(m, obj, method, [f(L) for f in args])
            return None, method_call
        if isinstance(call, n.Name):
            name = call.id
            spec = m.registry.functions.get(name)
            if spec is not None and spec.implementation is not None and spec.min_args == 0:
                implementation = spec.implementation
                return (lambda L: implementation()), None

            def not_callable(L: Locals) -> None:
                raise RunError(f"'{name}' is not a PROC" if name in m.globals or spec else f"'{name}' is not defined")
            return not_callable, None
        value = self.exprs.compile(call, scope)
        return (lambda L: value(L)), None

    def _routine_call(self, name: str, arguments: tuple[n.Argument, ...], scope: Scope, span: n.Span) -> Callable[[Locals], Iterator[object]]:
        """A call statement of a PROC or FUNC: a generator, so the pendant can step into it."""
        positional = [self.exprs.compile(a.value, scope) for a in arguments if a.name is None]
        named = {a.name.id: self.exprs.compile(a.value, scope) for a in arguments if a.name is not None}
        order = [p.id for p in self.scopes.routines[name].params]
        m = self.m

        def call(L: Locals) -> Iterator[object]:
            routine = m.routines[name]
            args = [f(L) for f in positional]
            if named:
                args = merge_named(name, order, args, {k: f(L) for k, f in named.items()})
            local_values = routine.bind(args)
            m.push(name, span, local_values)
            try:
                if routine.fast is not None and not m.trace:
                    routine.fast(local_values)
                else:
                    yield from routine.gen(local_values)
            except ReturnSignal:
                pass
            finally:
                m.pop()
        return call


def _assign_direct(store: Callable[[Locals, Any], None], value: Callable[[Locals], Any]) -> Callable[[Locals], None]:
    return lambda L: store(L, value(L))


def _is_io(target: n.Expression, scope: Scope, scopes: ProgramScopes) -> bool:
    """`DigOut[5] = 1`: an assignment to an IO channel (waits for the robot to arrive first)."""
    return (isinstance(target, n.Index) and isinstance(target.value, n.Name) and target.value.id in IO_BANKS
            and target.value.id not in scopes.globals and not scope.is_local(target.value.id))


def _seconds(value: Any, what: str) -> float:
    if type(value) is Quantity and value.dim == TIME:
        seconds = value.value
    elif type(value) in (int, float) and value == 0:
        seconds = 0.0
    else:
        raise RunError(f"{what} needs a time such as 0.5s, got {type_name(value)}")
    if seconds < 0:
        raise RunError(f"{what} needs a time >= 0, got {format_value(value)}")
    if not seconds <= MAX_DURATION_S:  # also not finite: a wait that never ends
        raise RunError(f"{what} of {format_value(value)} is longer than the longest allowed, {MAX_DURATION_S:g} s")
    return seconds

