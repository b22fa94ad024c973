"""Indentation of off-line text: a line-by-line plan of _INDENT/_DEDENT tokens, fed to Lark by a postlexer that never buffers."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Iterator

from lark import Token

#: A line that continues the motion or install statement above it.
_CONTINUATION = re.compile(r"[ \t]*(with|via|until)(?![A-Za-z0-9_])")
#: Lines that open a block.
_HEADER = re.compile(r"[ \t]*(if|elif|else|while|for|case|frame|try|except|def|func)(?![A-Za-z0-9_])")
#: Lines that continue the compound statement above them.
_MIDDLE = re.compile(r"[ \t]*(elif|else|except|end)(?![A-Za-z0-9_])")


@dataclass
class IndentProblem:
    """An indentation mistake: 1-based line and column."""

    line: int
    column: int
    message: str
    hint: str = ""


@dataclass
class IndentPlan:
    """For each 1-based line, the _INDENT (+1 each) and _DEDENT (-1 each) tokens that come before it."""

    before: dict[int, list[str]] = field(default_factory=dict)
    at_end: int = 0                                  #: dedents after the last line
    problems: list[IndentProblem] = field(default_factory=list)


def _outside_strings(text: str, wanted: str) -> int:
    """Index of the first `wanted` character outside string literals, or -1."""
    if '"' not in text:  # most lines: no string to step over
        return text.find(wanted)
    in_string, escaped = False, False
    for i, ch in enumerate(text):
        if in_string:
            if escaped:
                escaped = False
            elif ch == "\\":
                escaped = True
            elif ch == '"':
                in_string = False
        elif ch == '"':
            in_string = True
        elif ch == wanted:
            return i
    return -1


def code_part(text: str) -> str:
    """A line without its comment (a `#` inside a string is not a comment)."""
    hash_at = _outside_strings(text, "#")
    return text if hash_at < 0 else text[:hash_at]


def _opens_block(text: str) -> bool:
    """True when a line is a block header: it has a ':' outside strings and comments (only headers use ':')."""
    return _outside_strings(code_part(text), ":") >= 0


def _width(text: str) -> int:
    return len(text) - len(text.lstrip(" \t"))


def _continues(lines: list[str], number: int) -> bool:
    """True when the comment-only lines from line `number` on are followed by a continuation line."""
    for text in lines[number:]:
        if not text.strip(" \t\r").startswith("#"):
            return bool(_CONTINUATION.match(text))
    return False


def _middle_width(lines: list[str], number: int) -> int | None:
    """The indentation of the next line with code after line `number` when it is `else:`, `elif`, `except` or
    `end`; None otherwise."""
    for text in lines[number:]:
        stripped = text.strip(" \t\r")
        if stripped and not stripped.startswith("#"):
            return _width(text) if _MIDDLE.match(text) else None
    return None


def plan_indentation(lines: list[str]) -> IndentPlan:
    """Where blocks open and close. Blank lines go to the innermost block their own indentation reaches."""
    plan = IndentPlan()
    stack = [0]
    opener = False
    pending: list[tuple[int, int]] = []             # blank lines not yet placed: (line number, width)

    def emit(line: int, token: str) -> None:
        plan.before.setdefault(line, []).append(token)

    def close_to(target: int, line: int) -> None:
        """Dedent to `target`, placing waiting blank lines inside the blocks their width reaches."""
        for number, width in pending:
            while stack[-1] > target and stack[-1] > width:
                stack.pop()
                emit(number, "_DEDENT")
        while stack[-1] > target:
            stack.pop()
            emit(line, "_DEDENT")
        pending.clear()

    previous_blank = True
    last_statement, last_number = "", 0
    for number, text in enumerate(lines, start=1):
        stripped = text.strip(" \t\r")
        if not stripped:
            pending.append((number, _width(text)))
            previous_blank = True
            continue
        if not previous_blank and _CONTINUATION.match(text):
            continue  # the CONT token joins it to the line above
        if not previous_blank and stripped.startswith("#") and _continues(lines, number):
            continue  # a comment line between a statement and its continuation is part of the CONT token
        previous_blank = False
        width = _width(text)
        comment_only = stripped.startswith("#")
        middle = _middle_width(lines, number) if comment_only and width < stack[-1] else None
        if middle is not None and width <= middle:
            # `# ...` just before `else:`/`elif`/`except` at (or left of) the header's indentation stays in the
            # block above; one indented deeper than that keyword belongs where its indentation reaches
            continue
        if _MIDDLE.match(text) and pending:
            # Blank lines before `else:`, `elif`, `except` or `end` belong to the block above it: the header's
            # own block when the header is right above, else the block the keyword continues.
            inside = 1 << 30 if opener and width == stack[-1] else min((w for w in stack if w > width), default=width)
            pending[:] = [(line, max(w, inside)) for line, w in pending]
        if opener and width > stack[-1]:
            # The block's first line; blank lines between the header and it are inside the block.
            stack.append(width)
            emit(pending[0][0] if pending else number, "_INDENT")
            pending.clear()
            opener = False
        elif opener and pending and pending[0][1] > stack[-1]:
            # A block of blank lines only (printed with the block's indentation); it ends at the first shallower line.
            stack.append(pending[0][1])
            emit(pending[0][0], "_INDENT")
            opener = False
            close_to(width, number)
        elif width > stack[-1]:
            if not comment_only:
                hint = "only the lines of a block (after a line ending with ':') are indented"
                if _HEADER.match(last_statement):
                    hint = f"is a ':' missing at the end of line {last_number}?"
                plan.problems.append(IndentProblem(number, 1, "unexpected indentation", hint))
            close_to(stack[-1], number)
        else:
            close_to(width, number)
            if width != stack[-1] and not comment_only:
                plan.problems.append(IndentProblem(number, width + 1, "this line's indentation matches no enclosing block",
                                                   f"indent it by {stack[-1]} spaces"))
        if not comment_only:
            opener = _opens_block(text)
            last_statement, last_number = text, number
    if opener and pending and pending[0][1] > stack[-1]:
        # A block of blank lines at the end of the file.
        stack.append(pending[0][1])
        emit(pending[0][0], "_INDENT")
    for number, width in pending:
        while stack[-1] > 0 and stack[-1] > width:
            stack.pop()
            emit(number, "_DEDENT")
    plan.at_end = len(stack) - 1
    return plan


class OfflinePostLexer:
    """Inserts the planned _INDENT/_DEDENT tokens after each line break, as Lark consumes them (no lookahead)."""

    always_accept = ("_NL", "CONT", "COMMENT")

    def __init__(self) -> None:
        self.plan = IndentPlan()
        self.names: set[str] = set()   #: the NAME tokens of the last parse (are off-line keywords among them?)

    def _tokens(self, kinds: list[str], like: Token) -> Iterator[Token]:
        for kind in kinds:
            yield Token.new_borrow_pos(kind, "", like)

    def process(self, stream: Iterator[Token]) -> Iterator[Token]:
        last: Token | None = None
        names = self.names = set()
        before = self.plan.before
        for token in stream:
            kind = token.type
            if last is None:
                yield from self._tokens(before.get(1, []), token)
            yield token
            last = token
            if kind == "NAME":
                names.add(token.value)
            elif kind == "_NL":
                planned = before.get((token.line or 0) + 1)
                if planned:  # most lines open and close no block
                    yield from self._tokens(planned, token)
        if last is not None:
            yield from self._tokens(["_DEDENT"] * self.plan.at_end, last)
