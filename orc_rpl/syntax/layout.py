"""An edited tree printed in the layout of the text it came from: untouched statements keep their text byte for byte.

As LibCST keeps every space, but at the grain of statements: the base text is cut into one run of whole lines per
statement (its span, plus the blank and comment lines the tree places inside it), the new tree is aligned with the
base tree body by body, and every statement equal to its base statement is written as its base lines. A compound
statement whose header is unchanged keeps its header, separator and end lines and is aligned inside; everything else
is printed canonically at the indentation its block has in the base. The result is parsed back: when it does not give
the new tree (a layout the cutting cannot explain), the whole program is printed canonically instead, so the text is
never wrong, only less kept.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from difflib import SequenceMatcher
from typing import Callable

from orc_rpl.errors import OrcError
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax import offline_printer, printer
from orc_rpl.syntax.offline_parser import parse_offline
from orc_rpl.syntax.parser import parse

Lines = tuple[int, int]                          # first and last line of a run, 1-based, inclusive; empty when last < first


@dataclass(frozen=True)
class Syntax:
    """What the layout needs of one syntax: its canonical printers, its parser and its block indentation."""

    statement: Callable[[n.Statement, int], str]  #: canonical text of one statement at a depth, newline-terminated
    program: Callable[[n.Program], str]          #: canonical text of a whole program
    parse: Callable[[str, str], n.Program]
    indent: str                                  #: one canonical block level
    indented_trailing_blanks: bool               #: off-line: a blank line ending a block carries the block's indentation


def bodies(stmt: n.Statement) -> list[n.Body]:
    """The statement lists of a compound statement, in text order (none for a simple statement)."""
    if isinstance(stmt, n.If):
        return [b.body for b in stmt.branches] + ([stmt.else_body] if stmt.else_body is not None else [])
    if isinstance(stmt, (n.While, n.For, n.FrameBlock, n.Routine)):
        return [stmt.body]
    if isinstance(stmt, n.Try):
        return [stmt.body] + [h.body for h in stmt.handlers]
    if isinstance(stmt, n.Case):
        return [stmt.leading] + [a.body for a in stmt.arms] + ([stmt.else_arm.body] if stmt.else_arm is not None else [])
    return []


def _emptied(stmt: n.Statement) -> n.Statement:
    """The statement with every body empty: equal for two compounds whose header, separator and end lines are equal."""
    rep = dataclasses.replace
    if isinstance(stmt, n.If):
        else_body = () if stmt.else_body is not None else None
        return rep(stmt, branches=tuple(rep(b, body=()) for b in stmt.branches), else_body=else_body)
    if isinstance(stmt, (n.While, n.For, n.FrameBlock, n.Routine)):
        return rep(stmt, body=())
    if isinstance(stmt, n.Try):
        return rep(stmt, body=(), handlers=tuple(rep(h, body=()) for h in stmt.handlers))
    if isinstance(stmt, n.Case):
        else_arm = rep(stmt.else_arm, body=()) if stmt.else_arm is not None else None
        return rep(stmt, leading=(), arms=tuple(rep(a, body=()) for a in stmt.arms), else_arm=else_arm)
    return stmt


class _Unexplained(OrcError):
    """The spans do not cut the base text into the tree's statements; the layout is not kept."""


class _Base:
    """The base text as raw lines (every byte kept) and the runs of lines of its statements."""

    def __init__(self, text: str) -> None:
        pieces = text.split("\n")
        self.raw = [p + "\n" for p in pieces[:-1]] + ([pieces[-1]] if pieces[-1] else [])
        self.runs: dict[int, Lines] = {}            # id(statement) -> its lines

    def blank(self, number: int) -> bool:
        return 1 <= number <= len(self.raw) and not self.raw[number - 1].strip()

    def text(self, lines: Lines) -> list[str]:
        return self.raw[lines[0] - 1: lines[1]]

    def extent(self, stmt: n.Statement) -> int:
        """The last line of a statement: its last token, or later the blank lines its last block ends with."""
        last = stmt.span.end_line
        for body in reversed(bodies(stmt)):
            spanned = [i for i, s in enumerate(body) if not isinstance(s, n.Blank)]  # indices: equal statements repeat
            if spanned:
                return max(last, self.extent(body[spanned[-1]]) + len(body) - 1 - spanned[-1])
            if body:
                raise _Unexplained("a block of blank lines only")
        return last

    def cut(self, body: n.Body, first: int, last: int) -> None:
        """Give every statement of `body`, which fills lines first..last exactly, its run of lines."""
        line = first
        for stmt in body:
            if isinstance(stmt, n.Blank):
                if not self.blank(line):
                    raise _Unexplained(f"line {line} is not blank")
                self.runs[id(stmt)] = (line, line)
                line += 1
                continue
            if stmt.span.line != line:
                raise _Unexplained(f"a statement starts at line {stmt.span.line}, not {line}")
            end = self.extent(stmt)
            self.runs[id(stmt)] = (line, end)
            line = end + 1
        if line != last + 1:
            raise _Unexplained(f"lines {line}..{last} belong to no statement")

    def regions(self, stmt: n.Statement) -> list[Lines]:
        """Where each body of a compound statement stands inside its run (leading and trailing blank lines included)."""
        found: list[Lines] = []
        for body in bodies(stmt):
            spanned = [i for i, s in enumerate(body) if not isinstance(s, n.Blank)]
            if not spanned:
                if body:
                    raise _Unexplained("a block of blank lines only")
                found.append((0, -1))
                continue
            first, last = spanned[0], spanned[-1]
            found.append((body[first].span.line - first, self.extent(body[last]) + len(body) - 1 - last))
        return found


class _Printer:
    """The new tree written body by body against the base tree."""

    def __init__(self, syntax: Syntax, base: _Base) -> None:
        self.syntax = syntax
        self.base = base

    def indent_of(self, body: n.Body, outer: str) -> str:
        for stmt in body:
            if not isinstance(stmt, (n.Blank, n.Comment)):
                line = self.base.raw[stmt.span.line - 1]
                return line[: len(line) - len(line.lstrip(" \t"))]
        return outer + self.syntax.indent

    def canonical(self, stmt: n.Statement, indent: str, trailing_blank: bool) -> list[str]:
        if isinstance(stmt, n.Blank):
            return [(indent if trailing_blank and self.syntax.indented_trailing_blanks else "") + "\n"]
        text = self.syntax.statement(stmt, 0)
        return [(indent + line if line else line) + "\n" for line in text.split("\n")[:-1]]

    def body(self, new: n.Body, old: n.Body, indent: str) -> list[str]:
        out: list[str] = []
        trailing = len(new)
        while trailing > 0 and isinstance(new[trailing - 1], n.Blank):
            trailing -= 1
        matcher = SequenceMatcher(None, old, new, autojunk=False)
        for tag, i1, i2, j1, j2 in matcher.get_opcodes():
            for k in range(j2 - j1):
                stmt = new[j1 + k]
                if tag == "equal":
                    out += self.base.text(self.base.runs[id(old[i1 + k])])
                elif tag == "replace" and k < i2 - i1 and type(old[i1 + k]) is type(stmt) and bodies(stmt):
                    out += self.compound(stmt, old[i1 + k], indent, j1 + k >= trailing)
                else:
                    out += self.canonical(stmt, indent, j1 + k >= trailing)
        return out

    def compound(self, new: n.Statement, old: n.Statement, indent: str, trailing_blank: bool) -> list[str]:
        """A changed compound statement: its base header, separator and end lines kept when they did not change."""
        if _emptied(new) != _emptied(old):
            return self.canonical(new, indent, trailing_blank)
        try:
            regions = self.base.regions(old)
            old_bodies, new_bodies = bodies(old), bodies(new)
            for body, (first, last) in zip(old_bodies, regions):
                if body:
                    self.base.cut(body, first, last)
        except _Unexplained:
            return self.canonical(new, indent, trailing_blank)
        run_first, run_last = self.base.runs[id(old)]
        out: list[str] = []
        line = run_first
        for old_body, new_body, (first, last) in zip(old_bodies, new_bodies, regions):
            if not old_body:  # an empty base block: its statements come after the structural lines before it
                if new_body:
                    return self.canonical(new, indent, trailing_blank)
                continue
            out += self.base.text((line, first - 1))
            out += self.body(new_body, old_body, self.indent_of(old_body, indent))
            line = last + 1
        return out + self.base.text((line, run_last))


def print_keeping(program: n.Program, base_text: str, base: n.Program, syntax: Syntax, path: str = "<program>") -> str:
    """`program` in the layout of `base_text` (whose tree is `base`): canonical only where it differs from `base`."""
    return keep_layout(program, base_text, base, syntax, path)[0]


def keep_layout(program: n.Program, base_text: str, base: n.Program, syntax: Syntax,
                path: str = "<program>") -> tuple[str, n.Program | None]:
    """print_keeping's text and, when the layout was kept, its tree as parsed back (spans of the new text)."""
    cut = _Base(base_text)
    try:
        cut.cut(base.body, 1, len(cut.raw))
    except _Unexplained:
        return syntax.program(program), None
    text = "".join(_Printer(syntax, cut).body(program.body, base.body, ""))
    try:
        parsed: n.Program | None = syntax.parse(text, path)
    except OrcError:
        parsed = None
    if parsed != program:
        return syntax.program(program), None
    return text, parsed


#: The on-line syntax (`.rpl`): indentation is free, blank lines are empty.
ONLINE = Syntax(printer.print_statement, printer.print_program, parse, printer.INDENT, False)
#: The off-line syntax (`.orl`): indentation makes the blocks.
OFFLINE = Syntax(offline_printer.print_offline_statement, offline_printer.print_offline, parse_offline,
                 offline_printer.INDENT, True)


def print_online_keeping(program: n.Program, base_text: str, base: n.Program) -> str:
    """On-line text of `program`, keeping the layout of the on-line `base_text` it was edited or converted from."""
    return print_keeping(program, base_text, base, ONLINE)


def print_offline_keeping(program: n.Program, base_text: str, base: n.Program) -> str:
    """Off-line text of `program`, keeping the layout of the off-line `base_text` (OfflineSpellingError as print_offline)."""
    return print_keeping(program, base_text, base, OFFLINE)
