"""Compound statements compiled: IF, WHILE, FOR, CASE, FRAME blocks and TRY/ON."""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

from orc_rpl.executive import operators as ops
from orc_rpl.executive.blocks import Block, Locals
from orc_rpl.executive.machine import TICK
from orc_rpl.executive.scope import ProgramScopes, Scope
from orc_rpl.executive.signals import RunError
from orc_rpl.executive.values import IO_BANKS, type_name
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.limits import MAX_FOR_ITERATIONS
from orc_rpl.syntax.units import Quantity


class ControlFlow:
    """The compound statements of StatementCompiler (mixed in; uses its `block`, `exprs` and `store`)."""

    m: Any
    exprs: Any
    scopes: Any

    def block(self, body: n.Body, scope: Scope) -> Block:  # pragma: no cover - provided by StatementCompiler
        raise NotImplementedError

    def _if(self, stmt: n.If, scope: Scope) -> tuple[Any, Any]:
        m = self.m
        branches = [(self.exprs.condition(b.condition, scope), self.block(b.body, scope)) for b in stmt.branches]
        other = self.block(stmt.else_body, scope) if stmt.else_body is not None else None
        runners = [(cond, block.run(m)) for cond, block in branches]
        other_run = other.run(m) if other is not None else None

        def gen(L: Locals) -> Iterator[object]:
            for cond, run in runners:
                if cond(L):
                    yield from run(L)
                    return
            if other_run is not None:
                yield from other_run(L)

        if not all(block.fast for _, block in branches) or (other is not None and other.fast is None):
            return None, gen
        fasts = [(cond, block.fast) for cond, block in branches]
        other_fast = other.fast if other is not None else None
        if len(fasts) == 1 and other_fast is None:
            cond0, body0 = fasts[0]

            def fast_if(L: Locals) -> None:
                if cond0(L):
                    body0(L)
            return fast_if, gen

        def fast(L: Locals) -> None:
            for cond, body in fasts:
                if cond(L):
                    body(L)
                    return
            if other_fast is not None:
                other_fast(L)
        return fast, gen

    def _while(self, stmt: n.While, scope: Scope) -> tuple[Any, Any]:
        m = self.m
        cond = self.exprs.condition(stmt.condition, scope)
        body = self.block(stmt.body, scope)
        run = body.run(m)
        polling = reads_cell(stmt.condition, self.scopes)

        def gen(L: Locals) -> Iterator[object]:
            robot = m.robot
            while cond(L):
                m.count()
                yield from run(L)
                if polling:  # the cell only changes while time passes: one motion cycle per poll
                    robot.tick()
                    yield TICK

        if body.fast is None or polling:
            return None, gen
        body_fast = body.fast

        def fast(L: Locals) -> None:
            while cond(L):
                m.count()
                body_fast(L)
        return fast, gen

    def _for(self, stmt: n.For, scope: Scope) -> tuple[Any, Any]:
        m = self.m
        start, stop = self.exprs.compile(stmt.start, scope), self.exprs.compile(stmt.stop, scope)
        step = self.exprs.compile(stmt.step, scope) if stmt.step is not None else None
        store = self.store(stmt.variable.id, scope)  # type: ignore[attr-defined]
        body = self.block(stmt.body, scope)
        run = body.run(m)

        def values(L: Locals) -> Any:
            a, b = start(L), stop(L)
            c = step(L) if step is not None else 1
            if type(a) is int and type(b) is int and type(c) is int:
                if c == 0:
                    raise RunError("FOR ... STEP 0 would never end")
                return range(a, b + 1 if c > 0 else b - 1, c)
            return _stepped(a, b, c)

        def gen(L: Locals) -> Iterator[object]:
            for value in values(L):
                m.count()
                store(L, value)
                yield from run(L)

        if body.fast is None:
            return None, gen
        body_fast = body.fast

        def fast(L: Locals) -> None:
            for value in values(L):
                m.count()
                store(L, value)
                body_fast(L)
        return fast, gen

    def _case(self, stmt: n.Case, scope: Scope) -> tuple[Any, Any]:
        m = self.m
        subject = self.exprs.compile(stmt.subject, scope)

        def arm_block(arm: n.CaseArm) -> Block:
            return self.block(((arm.inline,) if arm.inline is not None else ()) + arm.body, scope)

        arms = [([self.exprs.compile(label, scope) for label in arm.labels], arm_block(arm)) for arm in stmt.arms]
        other = arm_block(stmt.else_arm) if stmt.else_arm is not None else None

        def select(L: Locals) -> Block | None:
            value = subject(L)
            for labels, block in arms:
                for label in labels:
                    if ops.equal(value, label(L)):
                        return block
            return other

        def gen(L: Locals) -> Iterator[object]:
            block = select(L)
            if block is not None:
                yield from block.run(m)(L)

        blocks = [b for _, b in arms] + ([other] if other is not None else [])
        if any(b.fast is None for b in blocks):
            return None, gen

        def fast(L: Locals) -> None:
            block = select(L)
            if block is not None:
                block.fast(L)  # type: ignore[misc]
        return fast, gen

    def _frameblock(self, stmt: n.FrameBlock, scope: Scope) -> tuple[Any, Any]:
        m, name = self.m, stmt.frame.id
        body = self.block(stmt.body, scope.with_frame(name))
        run = body.run(m)

        def enter() -> None:
            if name not in m.frames and name not in m.moving_frames():
                raise RunError(f"FRAME {name}: '{name}' is not a declared FRAME (declare it with FRAME {name} = POSE(...))")

        def gen(L: Locals) -> Iterator[object]:
            enter()
            yield from run(L)

        if body.fast is None:
            return None, gen
        body_fast = body.fast

        def fast(L: Locals) -> None:
            enter()
            body_fast(L)
        return fast, gen

    def _try(self, stmt: n.Try, scope: Scope) -> tuple[Any, Any]:
        m = self.m
        body = self.block(stmt.body, scope)
        handlers = [(frozenset(name.id for name in h.names),
                     self.block(((h.inline,) if h.inline is not None else ()) + h.body, scope)) for h in stmt.handlers]
        run = body.run(m)

        def handler_for(error: RunError) -> Block | None:
            if error.name is None:
                return None
            return next((block for names, block in handlers if error.name in names), None)

        def gen(L: Locals) -> Iterator[object]:
            try:
                yield from run(L)
                return
            except RunError as error:
                handler = handler_for(error)
                if handler is None:
                    raise
            yield from handler.run(m)(L)

        if body.fast is None or any(b.fast is None for _, b in handlers):
            return None, gen
        body_fast = body.fast

        def fast(L: Locals) -> None:
            try:
                body_fast(L)
                return
            except RunError as error:
                handler = handler_for(error)
                if handler is None:
                    raise
            handler.fast(L)  # type: ignore[misc]
        return fast, gen


def _stepped(a: Any, b: Any, c: Any) -> Iterator[Any]:
    """FOR over numbers or quantities: a, a+c, a+2c, ... while not past b (both bounds included)."""
    for value in (a, b, c):
        if type(value) not in (int, float, Quantity):
            raise RunError(f"FOR needs numbers or quantities, got {type_name(value)}")
    ops.less(a, b)  # the bounds' dimensions must agree...
    if type(a) is Quantity or type(c) is Quantity:
        ops.less(a, c)  # ...and the step's too
    from orc_rpl.syntax.units import magnitude

    step = magnitude(c)
    if step == 0:
        raise RunError("FOR ... STEP 0 would never end")
    _check_advances(a, b, c)
    k = 0
    while True:
        value = ops.add(a, ops.multiply(k, c))
        if (step > 0 and ops.greater(value, b)) or (step < 0 and ops.less(value, b)):
            return
        yield value
        k += 1


def _check_advances(a: Any, b: Any, c: Any) -> None:
    """A FOR whose counter cannot advance in floating point (`FROM 1e300`, `STEP 1e-300`) is an error, not a hang."""
    from orc_rpl.syntax.units import magnitude

    start, stop, step = float(magnitude(a)), float(magnitude(b)), float(magnitude(c))
    if not (math.isfinite(start) and math.isfinite(stop) and math.isfinite(step)):
        raise RunError("FOR needs finite bounds and step")
    if start + step == start:
        raise RunError(f"FOR cannot advance: {start:g} + STEP {step:g} is {start:g} again in floating point")
    iterations = (stop - start) / step
    if iterations > MAX_FOR_ITERATIONS:
        raise RunError(f"FOR would run about {iterations:.3g} times (at most {MAX_FOR_ITERATIONS:g}); use a larger STEP")


#: names whose value the cell changes while a program waits (a WHILE on them polls once per motion cycle)
_CELL_NAMES = frozenset({*IO_BANKS, "HERE", "ROBOT"})


def reads_cell(expr: n.Expression, scopes: ProgramScopes) -> bool:
    """True when an expression reads something the cell changes (IO, HERE, ROBOT, installed sensors)."""
    return any(isinstance(node, n.Name) and (node.id in _CELL_NAMES or node.id in scopes.installed) for node in expr.walk())
