"""Limits of what a program may write: nesting depth and number literals, checked once after parsing.

The tree walkers of the checker, the printers, the transformations and the executive recurse
over the tree; a program nested deeper than `MAX_NESTING` would exhaust Python's stack in any of
them, so the parser refuses it with a located error before any walker sees it.
"""

from __future__ import annotations

import math
import re

from orc_rpl.errors import Diagnostic, Location, SourceError
from orc_rpl.syntax import nodes as n

#: Deepest nesting of blocks and expressions (syntax-tree levels) a program may have.
MAX_NESTING = 200

#: Longest duration a WAIT, a TIMEOUT or a motion's `WITH TIME` may ask for (s): one day of simulated time.
MAX_DURATION_S = 86400.0

#: Most iterations a FOR over numbers may have: a loop that would need more cannot advance sensibly.
MAX_FOR_ITERATIONS = 1_000_000_000

#: Python refuses to convert integer strings longer than this (sys.get_int_max_str_digits()).
MAX_INTEGER_DIGITS = 4300

_DIGITS = re.compile(r"(\d+(?:\.\d*)?(?:[eE][+-]?\d+)?|\.\d+(?:[eE][+-]?\d+)?)")


def literal_problem(text: str) -> str | None:
    """Why a number literal as written cannot be a value (too many digits, not finite), or None."""
    match = _DIGITS.match(text)
    if match is None:
        return None
    digits = match.group(1)
    if digits.isdigit() and len(digits) > MAX_INTEGER_DIGITS:
        return f"integer literal with {len(digits)} digits is too long (at most {MAX_INTEGER_DIGITS})"
    with_unit = len(text) > match.end(1)  # a unit converts the number to a float (`1e400mm`, 400 digits and `mm`)
    if (with_unit or not digits.isdigit()) and not math.isfinite(float(digits)):
        return f"number literal '{text}' is too large (not a finite number)"
    return None


def _span_of(node: n.Node, fallback: n.Span) -> n.Span:
    return node.span if node.span.line else fallback


def nesting_problem(program: n.Node) -> tuple[n.Span, int] | None:
    """The span of the first node deeper than MAX_NESTING and its depth, or None (walked without recursion)."""
    stack: list[tuple[n.Node, int, n.Span]] = [(program, 0, program.span)]
    while stack:
        node, depth, around = stack.pop()
        span = _span_of(node, around)
        if depth > MAX_NESTING:
            return span, depth
        stack.extend((child, depth + 1, span) for child in node.children())
    return None


def check_nesting(program: n.Program, path: str, lines: list[str]) -> None:
    """Raise a located SourceError when the program nests deeper than the walkers can follow."""
    problem = nesting_problem(program)
    if problem is None:
        return
    span, _ = problem
    location = Location(path, max(1, span.line), max(1, span.column))
    raise SourceError([Diagnostic(location, f"nested too deeply (more than {MAX_NESTING} levels of blocks and expressions)",
                                  "split the block or the expression into smaller ones (PROC, FUNC or variables)")],
                      "\n".join(lines))
