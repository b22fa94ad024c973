"""Blocks of statements compiled into generators (for stepping and waiting) and plain functions (when nothing waits)."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

from orc_rpl.executive.machine import Machine
from orc_rpl.executive.signals import ReturnSignal, StopSignal
from orc_rpl.syntax import nodes as n

Locals = dict[str, Any]
Fast = Callable[[Locals], None]
Gen = Callable[[Locals], Iterator[object]]


@dataclass(slots=True)
class Compiled:
    """One statement: `fast` runs it when it cannot wait; `gen` runs it as a generator (always for waiting ones)."""

    node: n.Statement
    fast: Fast | None
    gen: Gen | None


@dataclass(slots=True)
class Block:
    """A compiled block: `gen` yields TICK while time passes and, when tracing, each statement before it runs."""

    gen: Gen
    fast: Fast | None          #: None when some statement in it may wait

    def run(self, m: Machine) -> Gen:
        """The generator to run now: the fast function wrapped, unless tracing or waiting is possible."""
        fast, gen = self.fast, self.gen
        if fast is None:
            return gen

        def run_gen(L: Locals) -> Iterator[object]:
            if m.trace:
                yield from gen(L)
            else:
                fast(L)
        return run_gen


_PASS_THROUGH = (ReturnSignal, StopSignal)


def make_block(m: Machine, items: list[Compiled]) -> Block:
    """A block from its compiled statements; each failure is located at the statement it happened in."""
    triples = [(c.node, c.fast, c.gen) for c in items]
    translate = m.translate

    count = m.count

    def gen(L: Locals) -> Iterator[object]:
        for node, fast, sub in triples:
            try:
                count()
                if m.trace:
                    yield node
                    if sub is not None:
                        yield from sub(L)
                        continue
                if fast is not None:
                    fast(L)
                else:
                    yield from sub(L)  # type: ignore[misc]
            except _PASS_THROUGH:
                raise
            except Exception as error:  # located here: the statement that failed
                raise translate(error, node.span) from None

    if not all(fast is not None for _, fast, _ in triples):
        return Block(gen, None)
    if len(triples) == 1:
        node0, fast0, _ = triples[0]

        def fast_one(L: Locals) -> None:
            try:
                count()
                fast0(L)  # type: ignore[misc]
            except _PASS_THROUGH:
                raise
            except Exception as error:
                raise translate(error, node0.span) from None
        return Block(gen, fast_one)

    def fast(L: Locals) -> None:
        for node, fn, _ in triples:
            try:
                count()
                fn(L)  # type: ignore[misc]
            except _PASS_THROUGH:
                raise
            except Exception as error:
                raise translate(error, node.span) from None
    return Block(gen, fast)


def wrap_errors(m: Machine, node: n.Statement, gen: Gen) -> Gen:
    """A statement's own generator with its failures located at it (for code run outside a block)."""
    def located(L: Locals) -> Iterator[object]:
        try:
            yield from gen(L)
        except _PASS_THROUGH:
            raise
        except Exception as error:
            raise m.translate(error, node.span) from None
    return located


__all__ = ["Block", "Compiled", "make_block", "wrap_errors"]
