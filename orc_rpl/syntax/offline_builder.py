"""Builds the one syntax tree from off-line parses: the on-line builder's rules, with the off-line spellings mapped onto them."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

from lark import Token

from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.builder import (
    BuildError, TreeBuilder, arrange, continuation_comments, expr, meta_span, name, token_span,
)

#: Off-line keywords (lower case); together with the on-line reserved words they are never names.
OFFLINE_KEYWORDS: frozenset[str] = frozenset(
    """moveto to along via with until if elif else while for in step case frame try except def func end return
    raise wait timeout print stop install as tool pos path var const enum and or not true false""".split()
)

#: Operators spelled differently off-line.
_OPERATORS = {"==": "=", "!=": "<>", "not": "NOT", "and": "AND", "or": "OR"}


def offline_comment(token: Token | None) -> str | None:
    """The text of a `#` comment token after the hash, trailing blanks removed."""
    if token is None:
        return None
    return str(token)[1:].rstrip()


def attribute_name(token: Token) -> n.Name:
    """`speed` -> SPEED: an all-lower-case attribute name is the upper-case on-line attribute; any other is kept."""
    word = str(token)
    if word == word.lower():
        word = word.upper()
    return n.Name(word, span=token_span(token))


@dataclass
class _End:
    """An explicit `end` line closing a block, with its comment."""

    comment: str | None


def _ending(c: list[Any]) -> tuple[list[Any], str | None]:
    """The children without a trailing `end` line, and that line's comment."""
    if c and isinstance(c[-1], _End):
        return c[:-1], c[-1].comment
    return c, None


class OfflineTreeBuilder(TreeBuilder):
    """Lark callbacks for orl.lark; rules shaped like the on-line ones are inherited."""

    # ---- lines
    def stmt_line(self, c: list[Any]) -> n.Statement:
        stmt = c[0]
        if len(c) > 1 and c[1] is not None:
            stmt = replace(stmt, comment=offline_comment(c[1]))
        return stmt

    def comment_line(self, c: list[Any]) -> n.Comment:
        return n.Comment(offline_comment(c[0]) or "", span=token_span(c[0]))

    def header_comment(self, c: list[Any]) -> str | None:
        return offline_comment(c[0]) if c else None

    def end_line(self, c: list[Any]) -> _End:
        return _End(offline_comment(c[1]) if len(c) > 1 else None)

    # ---- declarations and motion
    def declaration(self, c: list[Any]) -> n.Declaration:
        frame = c[3] if len(c) > 3 else None
        return n.Declaration(str(c[0]).upper(), name(c[1]), expr(c[2]), frame, span=meta_span(c))

    def install(self, c: list[Any]) -> n.Install:
        return n.Install(name(c[1]), name(c[2]), self._clauses(c[3:]), span=meta_span(c))  # type: ignore[arg-type]

    def motion(self, c: list[Any]) -> n.Motion:
        head = c[0]
        if head.type == "MOVETO":
            target = expr(c[1])
            to = n.To(target, span=target.span)
            return n.Motion("MOVE", n.Name("ARM", span=token_span(head)), (to,) + self._clauses(c[2:]), span=meta_span(c))
        return n.Motion(str(head).upper(), name(c[1]), self._clauses(c[2:]), span=meta_span(c))

    def with_clause(self, c: list[Any]) -> n.With:
        return n.With(attribute_name(c[0]), expr(c[1]), span=meta_span(c))

    @staticmethod
    def _clauses(parts: list[Any]) -> tuple[n.Clause, ...]:
        clauses: list[n.Clause] = []
        pending: Token | None = None
        for part in parts:
            if isinstance(part, Token) and part.type == "CONT":
                pending = part
                continue
            if pending is not None:
                comment, between = continuation_comments(str(pending), "#")
                part = replace(part, new_line=True, line_comment=comment, comments_before=between)
                pending = None
            clauses.append(part)
        return tuple(clauses)

    # ---- simple statements
    def wait_until(self, c: list[Any]) -> n.WaitUntil:
        return n.WaitUntil(expr(c[1]), expr(c[2]) if len(c) > 2 else None, span=meta_span(c))

    # ---- compound statements
    def if_stmt(self, c: list[Any]) -> n.If:
        c, comment = _ending(c)
        branches = [n.Branch(expr(c[1]), c[3], c[2], span=meta_span(c[:2]))]
        else_body, else_comment = None, None
        for part in c[4:]:
            if isinstance(part, n.Branch):
                branches.append(part)
            else:
                else_comment, else_body = part
        return n.If(tuple(branches), else_body, else_comment, comment, span=meta_span(c))

    def elif_part(self, c: list[Any]) -> n.Branch:
        return n.Branch(expr(c[1]), c[3], c[2], span=meta_span(c[:2]))

    def while_stmt(self, c: list[Any]) -> n.While:
        c, comment = _ending(c)
        return n.While(expr(c[1]), c[3], c[2], comment, span=meta_span(c))

    def for_stmt(self, c: list[Any]) -> n.For:
        c, comment = _ending(c)
        step = expr(c[6]) if len(c) == 9 else None
        return n.For(name(c[1]), expr(c[2]), expr(c[4]), step, c[-1], c[-2], comment, span=meta_span(c))

    def case_arm(self, c: list[Any]) -> n.CaseArm:
        return n.CaseArm(tuple(expr(x) for x in c[:-3]), c[-3], c[-1], c[-2], span=meta_span(c[:-3]))

    def case_else(self, c: list[Any]) -> n.CaseArm:
        return n.CaseArm((), c[1], c[3], c[2], span=token_span(c[0]))

    def case_stmt(self, c: list[Any]) -> n.Case:
        c, comment = _ending(c)
        subject, header_comment, items = expr(c[1]), c[2], c[3:]
        leading: list[n.Statement] = []
        arms: list[n.CaseArm] = []
        else_arm: n.CaseArm | None = None
        for item in items:
            if isinstance(item, n.CaseArm):
                if else_arm is not None:
                    raise BuildError("the else arm must be the last arm of a case", item.span)
                if item.labels:
                    arms.append(item)
                else:
                    else_arm = item
            elif else_arm is not None:
                # A comment or blank line between arms belongs to the arm above, as on-line.
                else_arm = replace(else_arm, body=else_arm.body + (item,))
            elif arms:
                arms[-1] = replace(arms[-1], body=arms[-1].body + (item,))
            else:
                leading.append(item)
        return n.Case(subject, tuple(arms), else_arm, header_comment, tuple(leading), comment, span=meta_span(c))

    def frame_block(self, c: list[Any]) -> n.FrameBlock:
        c, comment = _ending(c)
        return n.FrameBlock(name(c[1]), c[3], c[2], comment, span=meta_span(c))

    def try_stmt(self, c: list[Any]) -> n.Try:
        c, comment = _ending(c)
        return n.Try(c[2], tuple(c[3:]), c[1], comment, span=meta_span(c))

    def handler(self, c: list[Any]) -> n.Handler:
        names = tuple(name(t) for t in c[1:-3])
        return n.Handler(names, c[-3], c[-1], c[-2], span=meta_span(c[:-3]))

    def _routine(self, kind: str, c: list[Any]) -> n.Routine:
        c, comment = _ending(c)
        params = c[2] if len(c) == 5 else None
        return n.Routine(kind, name(c[1]), params or (), c[-1], params is not None, c[-2], comment, span=meta_span(c))

    # ---- expressions
    def unary(self, c: list[Any]) -> n.Unary:
        return n.Unary(_OPERATORS.get(str(c[0]), str(c[0])), expr(c[1]), span=meta_span(c))

    def expr(self, c: list[Any]) -> n.Expression:
        spelled = [Token.new_borrow_pos(x.type, _OPERATORS[str(x)], x) if isinstance(x, Token) and str(x) in _OPERATORS else x
                   for x in c]
        return arrange(spelled)


def check_names(program: n.Program) -> None:
    """Refuse off-line keywords used as names (the contextual lexer lets `x = to` through)."""
    fields = {id(node.name) for node in program.walk() if isinstance(node, n.Field)}
    for node in program.walk():
        if isinstance(node, n.Name) and id(node) not in fields and node.id in OFFLINE_KEYWORDS:
            raise BuildError(f"'{node.id}' is an off-line keyword and cannot be used as a name", node.span)
