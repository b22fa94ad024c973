"""Syntax tree -> canonical on-line text: one layout, comments where they were, parentheses only where needed."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from orc_rpl.syntax import nodes as n

#: Block bodies are indented by four spaces (the thesis' FRAME listing); continuation lines by two.
INDENT = "    "
CONTINUATION = "  "

#: Binding strength of operators; higher binds tighter.
_PRECEDENCE = {"OR": 1, "AND": 2, "NOT": 3, "=": 4, "<>": 4, "<": 4, "<=": 4, ">": 4, ">=": 4, "+": 5, "-": 5, "*": 6, "/": 6}
_UNARY_MINUS = 7
_POSTFIX = 8
_ATOM = 9


def precedence(expr: n.Expression) -> int:
    """How tightly an expression binds when it stands as an operand."""
    if isinstance(expr, n.Binary):
        return _PRECEDENCE[expr.op]
    if isinstance(expr, n.Unary):
        return _PRECEDENCE["NOT"] if expr.op == "NOT" else _UNARY_MINUS
    if isinstance(expr, (n.Field, n.Index, n.Call)):
        return _POSTFIX
    return _ATOM


def _wrap(text: str, needed: bool) -> str:
    return f"({text})" if needed else text


def quote(value: str) -> str:
    """A string literal for `value`."""
    escaped = value.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n").replace("\t", "\\t")
    return f'"{escaped}"'


@dataclass(frozen=True, slots=True)
class Spelling:
    """How one concrete syntax spells the tree's operators, booleans and keyword arguments."""

    operators: Mapping[str, str]            #: tree operator -> text, when it differs
    true: str
    false: str
    keyword_separator: str                  #: between an argument's name and its value

    def operator(self, op: str) -> str:
        return self.operators.get(op, op)


ONLINE = Spelling({}, "TRUE", "FALSE", " = ")


def expression(expr: n.Expression, spelling: Spelling = ONLINE) -> str:
    """Canonical text of an expression (on-line spelling unless told otherwise)."""
    if isinstance(expr, n.Number):
        return expr.text
    if isinstance(expr, n.Name):
        return expr.id
    if isinstance(expr, n.String):
        return quote(expr.value)
    if isinstance(expr, n.Boolean):
        return spelling.true if expr.value else spelling.false
    if isinstance(expr, n.ListExpr):
        return "[" + ", ".join(expression(item, spelling) for item in expr.items) + "]"
    if isinstance(expr, n.Binary):
        mine = _PRECEDENCE[expr.op]
        comparison = mine == _PRECEDENCE["="]
        left_needed = precedence(expr.left) < mine or (comparison and precedence(expr.left) == mine)
        left = _wrap(expression(expr.left, spelling), left_needed)
        right = _wrap(expression(expr.right, spelling), precedence(expr.right) <= mine)
        return f"{left} {spelling.operator(expr.op)} {right}"
    if isinstance(expr, n.Unary):
        operand = expression(expr.operand, spelling)
        if expr.op == "NOT":
            return spelling.operator("NOT") + " " + _wrap(operand, precedence(expr.operand) < _PRECEDENCE["NOT"])
        # `- -x` must not print as `--x`, which is a comment.
        needed = precedence(expr.operand) < _UNARY_MINUS or operand.startswith(("-", "+"))
        return expr.op + _wrap(operand, needed)
    if isinstance(expr, n.Field):
        # `(0).a`: a number right before `.` would swallow the dot.
        needed = precedence(expr.value) < _POSTFIX or isinstance(expr.value, n.Number)
        return _wrap(expression(expr.value, spelling), needed) + "." + expr.name.id
    if isinstance(expr, n.Index):
        value = _wrap(expression(expr.value, spelling), precedence(expr.value) < _POSTFIX)
        return value + "[" + expression(expr.index, spelling) + "]"
    if isinstance(expr, n.Call):
        function = _wrap(expression(expr.function, spelling), precedence(expr.function) < _POSTFIX)
        return function + "(" + ", ".join(argument(a, spelling) for a in expr.arguments) + ")"
    raise TypeError(f"not an expression node: {expr!r}")


def argument(arg: n.Argument, spelling: Spelling = ONLINE) -> str:
    """`value` or `name = value`; a positional equality is parenthesized where it would read as a keyword."""
    value = expression(arg.value, spelling)
    if arg.name is not None:
        return f"{arg.name.id}{spelling.keyword_separator}{value}"
    if isinstance(arg.value, n.Binary) and spelling.operator(arg.value.op) == "=":
        return f"({value})"
    return value


def _trailing(comment: str | None) -> str:
    return "" if comment is None else f"  --{comment}"


class _Writer:
    """Collects output lines at an indentation level."""

    def __init__(self) -> None:
        self.lines: list[str] = []

    def line(self, depth: int, text: str, comment: str | None = None) -> None:
        self.lines.append((INDENT * depth + text + _trailing(comment)) if text or comment is not None else "")

    def body(self, statements: n.Body, depth: int) -> None:
        for stmt in statements:
            self.statement(stmt, depth)

    def clauses(self, depth: int, head: str, clauses: tuple[n.Clause, ...], comment: str | None) -> None:
        text = head
        for clause in clauses:
            if clause.new_line:
                self.line(depth, text, clause.line_comment)
                for between in clause.comments_before:
                    self.lines.append(INDENT * depth + CONTINUATION + "--" + between)
                text = CONTINUATION + clause_text(clause)
            else:
                text += " " + clause_text(clause)
        self.line(depth, text, comment)

    def statement(self, stmt: n.Statement, depth: int) -> None:
        if isinstance(stmt, n.Blank):
            self.lines.append("")
        elif isinstance(stmt, n.Comment):
            self.lines.append(INDENT * depth + "--" + stmt.text)
        elif isinstance(stmt, n.Motion):
            self.clauses(depth, f"{stmt.keyword} {stmt.tool.id}", stmt.clauses, stmt.comment)
        elif isinstance(stmt, n.Install):
            self.clauses(depth, f"INSTALL {stmt.name.id} AS {stmt.kind.id}", stmt.attributes, stmt.comment)
        elif isinstance(stmt, n.If):
            self._if(stmt, depth)
        elif isinstance(stmt, n.While):
            self.line(depth, f"WHILE {expression(stmt.condition)} DO", stmt.header_comment)
            self.body(stmt.body, depth + 1)
            self.line(depth, "ENDWHILE", stmt.comment)
        elif isinstance(stmt, n.For):
            step = f" STEP {expression(stmt.step)}" if stmt.step is not None else ""
            head = f"FOR {stmt.variable.id} FROM {expression(stmt.start)} TO {expression(stmt.stop)}{step} DO"
            self.line(depth, head, stmt.header_comment)
            self.body(stmt.body, depth + 1)
            self.line(depth, "ENDFOR", stmt.comment)
        elif isinstance(stmt, n.Case):
            self._case(stmt, depth)
        elif isinstance(stmt, n.FrameBlock):
            self.line(depth, f"FRAME {stmt.frame.id}", stmt.header_comment)
            self.body(stmt.body, depth + 1)
            self.line(depth, "ENDFRAME", stmt.comment)
        elif isinstance(stmt, n.Try):
            self.line(depth, "TRY", stmt.header_comment)
            self.body(stmt.body, depth + 1)
            for handler in stmt.handlers:
                names = ", ".join(name.id for name in handler.names)
                self._arm(depth, f"ON {names} :", handler.inline, handler.header_comment, handler.body)
            self.line(depth, "ENDTRY", stmt.comment)
        elif isinstance(stmt, n.Routine):
            params = "(" + ", ".join(p.id for p in stmt.params) + ")" if stmt.parenthesized or stmt.params else ""
            self.line(depth, f"{stmt.kind} {stmt.name.id}{params}", stmt.header_comment)
            self.body(stmt.body, depth + 1)
            self.line(depth, f"END{stmt.kind}", stmt.comment)
        else:
            self.line(depth, simple_statement(stmt), getattr(stmt, "comment", None))

    def _arm(self, depth: int, head: str, inline: n.Statement | None, comment: str | None, body: n.Body) -> None:
        if isinstance(inline, n.Motion):
            self.clauses(depth, f"{head} {inline.keyword} {inline.tool.id}", inline.clauses, comment)
        elif isinstance(inline, n.Install):
            self.clauses(depth, f"{head} INSTALL {inline.name.id} AS {inline.kind.id}", inline.attributes, comment)
        else:
            self.line(depth, head + (" " + simple_statement(inline) if inline is not None else ""), comment)
        self.body(body, depth + 1)

    def _if(self, stmt: n.If, depth: int) -> None:
        for i, branch in enumerate(stmt.branches):
            keyword = "IF" if i == 0 else "ELSIF"
            self.line(depth, f"{keyword} {expression(branch.condition)} THEN", branch.header_comment)
            self.body(branch.body, depth + 1)
        if stmt.else_body is not None:
            self.line(depth, "ELSE", stmt.else_comment)
            self.body(stmt.else_body, depth + 1)
        self.line(depth, "ENDIF", stmt.comment)

    def _case(self, stmt: n.Case, depth: int) -> None:
        self.line(depth, f"CASE {expression(stmt.subject)} OF", stmt.header_comment)
        self.body(stmt.leading, depth + 1)
        for arm in stmt.arms:
            labels = ", ".join(expression(label) for label in arm.labels)
            self._arm(depth + 1, f"{labels} :", arm.inline, arm.header_comment, arm.body)
        if stmt.else_arm is not None:
            arm = stmt.else_arm
            self._arm(depth + 1, "ELSE :", arm.inline, arm.header_comment, arm.body)
        self.line(depth, "ENDCASE", stmt.comment)


def clause_text(clause: n.Clause) -> str:
    """One motion clause without its line break."""
    if isinstance(clause, n.To):
        return f"TO {expression(clause.target)}"
    if isinstance(clause, n.Along):
        return f"ALONG {expression(clause.path)}"
    if isinstance(clause, n.Via):
        return "VIA " + ", ".join(expression(p) for p in clause.points)
    if isinstance(clause, n.With):
        return f"WITH {clause.name.id} = {expression(clause.value)}"
    if isinstance(clause, n.Until):
        return f"UNTIL {expression(clause.condition)}"
    raise TypeError(f"not a clause: {clause!r}")


def simple_statement(stmt: n.Statement) -> str:
    """Canonical text of a one-line statement, without its comment."""
    if isinstance(stmt, n.Declaration):
        frame = f" IN {stmt.frame.id}" if stmt.frame is not None else ""
        return f"{stmt.kind} {stmt.name.id} = {expression(stmt.value)}{frame}"
    if isinstance(stmt, n.EnumDecl):
        return f"ENUM {stmt.name.id} = " + ", ".join(m.id for m in stmt.members)
    if isinstance(stmt, n.Assign):
        return f"{expression(stmt.target)} = {expression(stmt.value)}"
    if isinstance(stmt, n.CallStatement):
        return expression(stmt.call)
    if isinstance(stmt, n.Wait):
        return f"WAIT {expression(stmt.duration)}"
    if isinstance(stmt, n.WaitUntil):
        timeout = f" TIMEOUT {expression(stmt.timeout)}" if stmt.timeout is not None else ""
        return f"WAIT UNTIL {expression(stmt.condition)}{timeout}"
    if isinstance(stmt, n.Print):
        return ("PRINT " + ", ".join(expression(v) for v in stmt.values)) if stmt.values else "PRINT"
    if isinstance(stmt, n.Raise):
        return f"RAISE {stmt.name.id}"
    if isinstance(stmt, n.Return):
        return "RETURN" + (f" {expression(stmt.value)}" if stmt.value is not None else "")
    if isinstance(stmt, n.Stop):
        return "STOP"
    if isinstance(stmt, n.Motion):
        return f"{stmt.keyword} {stmt.tool.id} " + " ".join(clause_text(c) for c in stmt.clauses)
    raise TypeError(f"not a one-line statement: {type(stmt).__name__}")


def print_statement(stmt: n.Statement, depth: int = 0) -> str:
    """Canonical text of one statement (several lines for a block), newline-terminated."""
    writer = _Writer()
    writer.statement(stmt, depth)
    return "\n".join(writer.lines) + "\n"


def print_program(program: n.Program) -> str:
    """Canonical text of a whole program."""
    writer = _Writer()
    writer.body(program.body, 0)
    return "\n".join(writer.lines) + "\n" if writer.lines else ""
