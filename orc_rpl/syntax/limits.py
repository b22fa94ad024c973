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


#: Most tree levels a statement adds beyond one per character of its line (the statement, its clause, its WITH...).
_LEVELS_WITHOUT_TEXT = 8


def nesting_problem(program: n.Node, lines: list[str] | None = None) -> tuple[n.Span, int] | None:
    """The span of the first node deeper than MAX_NESTING and its depth, or None (walked without recursion).

    With the program's `lines`, a statement on one line is not walked when it cannot reach the limit: below the
    statement level every tree level takes at least one character of the line (`(`, `[`, `-`, an operator and its
    operand), so such a statement is at most its line's length and a few levels deep.
    """
    stack: list[tuple[n.Node, int, n.Span]] = [(program, 0, program.span)]
    limit = MAX_NESTING - _LEVELS_WITHOUT_TEXT
    count = len(lines) if lines is not None else 0
    while stack:
        node, depth, around = stack.pop()
        span = _span_of(node, around)
        if depth > MAX_NESTING:
            return span, depth
        line = node.span.line
        if (0 < line <= count and line == node.span.end_line and isinstance(node, n.Statement)
                and not isinstance(node, n.Routine) and depth + len(lines[line - 1]) <= limit):  # type: ignore[index]
            continue
        stack.extend((child, depth + 1, span) for child in node.children())
    return None


def check_nesting(program: n.Program, path: str, lines: list[str]) -> None:
    """Raise a located SourceError when the program nests deeper than the walkers can follow."""
    problem = nesting_problem(program, lines)
    if problem is None:
        return
    span, _ = problem
    location = Location(path, max(1, span.line), max(1, span.column))
    raise SourceError([Diagnostic(location, f"nested too deeply (more than {MAX_NESTING} levels of blocks and expressions)",
                                  "split the block or the expression into smaller ones (PROC, FUNC or variables)")],
                      "\n".join(lines))
