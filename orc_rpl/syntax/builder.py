"""Builds the syntax tree from Lark's parse, rule by rule, during parsing (no intermediate parse tree)."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

from lark import Token, Transformer

from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.lexicon import is_reserved
from orc_rpl.syntax.limits import MAX_NESTING, literal_problem


class BuildError(Exception):
    """A construct that parsed but is not valid RPL (a reserved word as a name, `f(x) = 1`)."""

    def __init__(self, message: str, span: n.Span, hint: str = "") -> None:
        super().__init__(message)
        self.message = message
        self.span = span
        self.hint = hint


def token_span(token: Token) -> n.Span:
    """The span of one token."""
    return n.Span(token.line, token.column, token.end_line, token.end_column)


def _start(child: Any) -> n.Span | None:
    if isinstance(child, Token):
        return token_span(child)
    if isinstance(child, n.Node):
        return child.span if child.span.line else None
    if isinstance(child, tuple):
        for item in child:
            found = _start(item)
            if found:
                return found
    if isinstance(child, (_Label, _Else)):
        return child.span
    return None


def _end(child: Any) -> n.Span | None:
    if isinstance(child, tuple):
        for item in reversed(child):
            found = _end(item)
            if found:
                return found
        return None
    return _start(child)


def meta_span(children: list[Any]) -> n.Span:
    """The span of a rule: from its first token to its last (keywords dropped by the grammar are not seen)."""
    # The common cases first, without making a Span per child: the parser calls this for every rule it reduces.
    head, tail = children[0] if children else None, children[-1] if children else None
    if type(head) is Token and type(tail) is Token:
        return n.Span(head.line, head.column, tail.end_line, tail.end_column)
    first = next((s for s in map(_start, children) if s), None)
    if first is None:
        return n.NO_SPAN
    if type(tail) is Token:
        return n.Span(first.line, first.column, tail.end_line, tail.end_column)
    last = next((s for s in map(_end, reversed(children)) if s), first)
    return n.Span(first.line, first.column, last.end_line, last.end_column)


def unescape(literal: str) -> str:
    """The value of a string literal (quotes removed, `\\"` and `\\\\` resolved)."""
    body = literal[1:-1]
    if "\\" not in body:
        return body
    out, i = [], 0
    while i < len(body):
        ch = body[i]
        if ch == "\\" and i + 1 < len(body):
            nxt = body[i + 1]
            out.append({"n": "\n", "t": "\t"}.get(nxt, nxt))
            i += 2
        else:
            out.append(ch)
            i += 1
    return "".join(out)


def continuation_comments(text: str, marker: str) -> tuple[str | None, tuple[str, ...]]:
    """The comments a CONT token holds: the one ending the line above, and the comment-only lines in between."""
    lines = text.split("\n")[:-1]  # the last piece is the continuation line's indentation
    first = lines[0].rstrip("\r")
    between = tuple(line.strip(" \t\r")[len(marker):].rstrip() for line in lines[1:])
    return (first[len(marker):].rstrip() if first.startswith(marker) else None), between


def comment_text(token: Token | None) -> str | None:
    """The text of a `--` comment token after the dashes, trailing blanks removed."""
    if token is None:
        return None
    return str(token)[2:].rstrip()


def name(token: Token) -> n.Name:
    """A Name node from a NAME token, refusing reserved words."""
    word = str(token)
    if is_reserved(word):
        raise BuildError(f"'{word}' is a reserved word and cannot be used as a name", token_span(token))
    return n.Name(word, span=token_span(token))


def expr(child: Any) -> n.Expression:
    """An expression node from a rule result or a bare token (atoms are inlined by the grammar)."""
    if isinstance(child, n.Expression):
        return child
    if isinstance(child, Token):
        span = token_span(child)
        kind = child.type
        if kind == "NAME":
            return name(child)
        if kind == "NUMBER":
            problem = literal_problem(str(child))
            if problem is not None:
                raise BuildError(problem, span)
            return n.Number(str(child), span=span)
        if kind == "STRING":
            return n.String(unescape(str(child)), span=span)
        if kind in ("TRUE", "FALSE"):
            return n.Boolean(kind == "TRUE", span=span)
        raise BuildError(f"unexpected {str(child)!r}", span)
    raise BuildError("expected an expression", n.NO_SPAN)


@dataclass
class _Label:
    """A CASE label line, before arms are grouped."""

    labels: tuple[n.Expression, ...]
    inline: n.Statement | None
    header_comment: str | None
    span: n.Span


@dataclass
class _Else:
    """An `ELSE :` line of a CASE."""

    inline: n.Statement | None
    header_comment: str | None
    span: n.Span


def _clauses(parts: list[Any]) -> tuple[n.Clause, ...]:
    """Clauses in source order; a CONT token marks that the next clause starts a continuation line."""
    clauses: list[n.Clause] = []
    pending: Token | None = None
    for part in parts:
        if isinstance(part, Token) and part.type == "CONT":
            pending = part
            continue
        if pending is not None:
            comment, between = continuation_comments(str(pending), "--")
            part = replace(part, new_line=True, line_comment=comment, comments_before=between)
            pending = None
        clauses.append(part)
    return tuple(clauses)


#: Binding strength of binary operators (higher binds tighter); NOT sits between AND and comparisons.
BINARY_PRECEDENCE = {"OR": 1, "AND": 2, "=": 4, "<>": 4, "<": 4, "<=": 4, ">": 4, ">=": 4, "+": 5, "-": 5, "*": 6, "/": 6}
NOT_PRECEDENCE = 3
_COMPARISON = 4


def arrange(items: list[Any]) -> n.Expression:
    """Operands and operators parsed flat, arranged by precedence (left-associative, comparisons not chained)."""
    if len(items) == 3 and not (isinstance(items[0], Token) and items[0].type == "NOT"):
        left, op, right = items  # `a + b`, the common case: one operator (three items: `NOT NOT a` or this)
        left, right = expr(left), expr(right)
        return n.Binary(str(op), left, right, span=_join(left.span, right.span))
    return _Arranger(items).climb(0)


class _Arranger:
    """Precedence climbing over one flat expression (an object, not closures: recursive closures are cyclic garbage)."""

    __slots__ = ("items", "position", "nots")

    def __init__(self, items: list[Any]) -> None:
        self.items, self.position = items, 0
        self.nots = 0  # NOTs in a row recurse here, before the tree exists to be measured

    def operand(self) -> n.Expression:
        item = self.items[self.position]
        self.position += 1
        if isinstance(item, Token) and item.type == "NOT":
            self.nots += 1
            if self.nots > MAX_NESTING:
                raise BuildError(f"nested too deeply (more than {MAX_NESTING} levels of blocks and expressions)",
                                 token_span(item))
            inner = self.climb(_COMPARISON)  # NOT a = b means NOT (a = b)
            self.nots -= 1
            return n.Unary("NOT", inner, span=_join(token_span(item), inner.span))
        return expr(item)

    def climb(self, min_precedence: int) -> n.Expression:
        items = self.items
        left = self.operand()
        fresh_comparison = False
        while self.position < len(items):
            op = items[self.position]
            precedence = BINARY_PRECEDENCE[str(op)]
            if precedence < min_precedence:
                break
            if precedence == _COMPARISON and fresh_comparison:
                raise BuildError("comparisons cannot be chained; combine them with AND", token_span(op),
                                 hint="write `a < b AND b < c`")
            self.position += 1
            right = self.climb(precedence + 1)
            left = n.Binary(str(op), left, right, span=_join(left.span, right.span))
            fresh_comparison = precedence == _COMPARISON
        return left


def _positional(value: n.Expression) -> n.Argument:
    return n.Argument(None, value, span=value.span)


def _join(a: n.Span, b: n.Span) -> n.Span:
    return n.Span(a.line, a.column, b.end_line, b.end_column)


class TreeBuilder(Transformer):
    """Lark callbacks, one per grammar rule, returning syntax-tree nodes (children as Lark gives them)."""

    # ---- lines
    def program(self, c: list[Any]) -> n.Program:
        return n.Program(tuple(c), span=meta_span(c))

    def stmt_line(self, c: list[Any]) -> n.Statement:
        stmt = c[0]
        if len(c) > 1:
            stmt = replace(stmt, comment=comment_text(c[1]))
        return stmt

    def comment_line(self, c: list[Any]) -> n.Comment:
        return n.Comment(comment_text(c[0]) or "", span=token_span(c[0]))

    def blank_line(self, c: list[Any]) -> n.Blank:
        return n.Blank()

    def block(self, c: list[Any]) -> n.Body:
        return tuple(c)

    def header_comment(self, c: list[Any]) -> str | None:
        return comment_text(c[0]) if c else None

    # ---- declarations
    def declaration(self, c: list[Any]) -> n.Declaration:
        frame = c[3] if len(c) > 3 else None
        return n.Declaration(str(c[0]), name(c[1]), expr(c[2]), frame, span=meta_span(c))

    def in_frame(self, c: list[Any]) -> n.Name:
        return name(c[0])

    def enum_decl(self, c: list[Any]) -> n.EnumDecl:
        return n.EnumDecl(name(c[1]), tuple(name(t) for t in c[2:]), span=meta_span(c))

    def install(self, c: list[Any]) -> n.Install:
        return n.Install(name(c[1]), name(c[2]), _clauses(c[3:]), span=meta_span(c))  # type: ignore[arg-type]

    # ---- motion
    def motion(self, c: list[Any]) -> n.Motion:
        return n.Motion(str(c[0]), name(c[1]), _clauses(c[2:]), span=meta_span(c))

    def to_clause(self, c: list[Any]) -> n.To:
        return n.To(expr(c[0]), span=meta_span(c))

    def along_clause(self, c: list[Any]) -> n.Along:
        return n.Along(expr(c[0]), span=meta_span(c))

    def via_clause(self, c: list[Any]) -> n.Via:
        return n.Via(tuple(expr(x) for x in c), span=meta_span(c))

    def with_clause(self, c: list[Any]) -> n.With:
        return n.With(name(c[0]), expr(c[1]), span=meta_span(c))

    def until_clause(self, c: list[Any]) -> n.Until:
        return n.Until(expr(c[0]), span=meta_span(c))

    # ---- simple statements
    def expr_stmt(self, c: list[Any]) -> n.Statement:
        target = expr(c[0])
        span = meta_span(c)
        if len(c) == 2:
            if not isinstance(target, (n.Name, n.Field, n.Index)):
                raise BuildError("only a name, a field or an indexed element can be assigned", target.span)
            return n.Assign(target, expr(c[1]), span=span)
        if not isinstance(target, (n.Name, n.Field, n.Call)):
            raise BuildError("this expression is not a statement; assign it or call something", target.span,
                             hint="write `x = ...` to keep a value")
        return n.CallStatement(target, span=span)

    def wait_time(self, c: list[Any]) -> n.Wait:
        return n.Wait(expr(c[1]), span=meta_span(c))

    def wait_until(self, c: list[Any]) -> n.WaitUntil:
        return n.WaitUntil(expr(c[1]), expr(c[2]) if len(c) > 2 else None, span=meta_span(c))

    def print_stmt(self, c: list[Any]) -> n.Print:
        return n.Print(tuple(expr(x) for x in c[1:]), span=meta_span(c))

    def raise_stmt(self, c: list[Any]) -> n.Raise:
        return n.Raise(name(c[1]), span=meta_span(c))

    def return_stmt(self, c: list[Any]) -> n.Return:
        return n.Return(expr(c[1]) if len(c) > 1 else None, span=meta_span(c))

    def stop_stmt(self, c: list[Any]) -> n.Stop:
        return n.Stop(span=meta_span(c))

    # ---- compound statements
    def if_stmt(self, c: list[Any]) -> n.If:
        condition = expr(c[1])
        branches = [n.Branch(condition, c[3], c[2], span=meta_span(c[:2]))]
        else_body, else_comment = None, None
        for part in c[4:-1]:
            if isinstance(part, n.Branch):
                branches.append(part)
            else:
                else_comment, else_body = part
        return n.If(tuple(branches), else_body, else_comment, span=meta_span(c))

    def elsif_part(self, c: list[Any]) -> n.Branch:
        return n.Branch(expr(c[1]), c[3], c[2], span=meta_span(c[:2]))

    def else_part(self, c: list[Any]) -> tuple[str | None, n.Body]:
        return c[1], c[2]

    def while_stmt(self, c: list[Any]) -> n.While:
        return n.While(expr(c[1]), c[3], c[2], span=meta_span(c))

    def for_stmt(self, c: list[Any]) -> n.For:
        step = expr(c[4]) if len(c) == 8 else None
        return n.For(name(c[1]), expr(c[2]), expr(c[3]), step, c[-2], c[-3], span=meta_span(c))

    def case_label(self, c: list[Any]) -> _Label:
        return _Label(tuple(expr(x) for x in c[:-2]), c[-2], c[-1], meta_span(c[:-2]))

    def case_else(self, c: list[Any]) -> _Else:
        return _Else(c[1], c[2], token_span(c[0]))

    def negative(self, c: list[Any]) -> n.Expression:
        return n.Unary(str(c[0]), expr(c[1]), span=meta_span(c))

    def inline_stmt(self, c: list[Any]) -> n.Statement | None:
        return c[0] if c else None

    def case_stmt(self, c: list[Any]) -> n.Case:
        subject, header_comment, items = expr(c[1]), c[2], c[3:-1]
        leading: list[n.Statement] = []
        arms: list[n.CaseArm] = []
        else_arm: n.CaseArm | None = None
        current: _Label | _Else | None = None
        body: list[n.Statement] = []

        def close() -> None:
            nonlocal else_arm
            if isinstance(current, _Label):
                arms.append(n.CaseArm(current.labels, current.inline, tuple(body), current.header_comment, span=current.span))
            elif isinstance(current, _Else):
                else_arm = n.CaseArm((), current.inline, tuple(body), current.header_comment, span=current.span)

        for item in items:
            if isinstance(item, (_Label, _Else)):
                if isinstance(current, _Else):
                    raise BuildError("the ELSE arm must be the last arm of a CASE", item.span)
                close()
                current, body = item, []
            elif current is None:
                if not isinstance(item, (n.Comment, n.Blank)):
                    raise BuildError("a statement inside CASE must follow a label (`value :`)", item.span)
                leading.append(item)
            else:
                body.append(item)
        close()
        return n.Case(subject, tuple(arms), else_arm, header_comment, tuple(leading), span=meta_span(c))

    def frame_block(self, c: list[Any]) -> n.FrameBlock:
        return n.FrameBlock(name(c[1]), c[3], c[2], span=meta_span(c))

    def try_stmt(self, c: list[Any]) -> n.Try:
        return n.Try(c[2], tuple(c[3:-1]), c[1], span=meta_span(c))

    def handler(self, c: list[Any]) -> n.Handler:
        names = tuple(name(t) for t in c[1:-3])
        return n.Handler(names, c[-3], c[-1], c[-2], span=meta_span(c[:-3]))

    def proc(self, c: list[Any]) -> n.Routine:
        return self._routine("PROC", c)

    def func(self, c: list[Any]) -> n.Routine:
        return self._routine("FUNC", c)

    def _routine(self, kind: str, c: list[Any]) -> n.Routine:
        params = c[2] if len(c) == 6 else None
        return n.Routine(kind, name(c[1]), params or (), c[-2], params is not None, c[-3], span=meta_span(c))

    def params(self, c: list[Any]) -> tuple[n.Name, ...]:
        return tuple(name(t) for t in c)

    # ---- expressions
    def expr(self, c: list[Any]) -> n.Expression:
        return arrange(c)

    def unary(self, c: list[Any]) -> n.Unary:
        return n.Unary(str(c[0]), expr(c[1]), span=meta_span(c))

    def field(self, c: list[Any]) -> n.Field:
        return n.Field(expr(c[0]), n.Name(str(c[1]), span=token_span(c[1])), span=meta_span(c))

    def index(self, c: list[Any]) -> n.Index:
        return n.Index(expr(c[0]), expr(c[1]), span=meta_span(c))

    def call(self, c: list[Any]) -> n.Call:
        arguments = c[1] if c[1] is not None else ()
        return n.Call(expr(c[0]), arguments, span=meta_span(c))

    def args(self, c: list[Any]) -> tuple[n.Argument, ...]:
        return tuple(a if isinstance(a, n.Argument) else _positional(expr(a)) for a in c)

    def keyword_arg(self, c: list[Any]) -> n.Argument:
        return n.Argument(name(c[0]), expr(c[1]), span=meta_span(c))

    def list_expr(self, c: list[Any]) -> n.ListExpr:
        # the brackets are kept by the grammar: an empty list `[]` has no other place to point at
        return n.ListExpr(tuple(expr(x) for x in c[1:-1] if x is not None), span=meta_span(c))
