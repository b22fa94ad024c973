"""Syntax tree -> canonical off-line text (`.orl`): lower-case keywords, indented blocks, `#` comments where they were."""

from __future__ import annotations

from orc_rpl.errors import OrcError
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.printer import Spelling
from orc_rpl.syntax.printer import expression as online_expression

#: Blocks and continuation lines are indented by four spaces.
INDENT = "    "

#: The off-line spelling of the operators and booleans (docs/language.md section 10).
OFFLINE = Spelling({"=": "==", "<>": "!=", "AND": "and", "OR": "or", "NOT": "not"}, "true", "false", "=")


class OfflineSpellingError(OrcError):
    """A tree that has no off-line spelling (an attribute name such as `speed` written in lower case on-line)."""


def expression(expr: n.Expression) -> str:
    """Canonical off-line text of an expression: the on-line printer with the off-line spelling."""
    return online_expression(expr, OFFLINE)


def attribute_name(name: n.Name) -> str:
    """SPEED -> speed; a name with lower-case letters (`Id`) is written as it is."""
    word = name.id
    if word == word.upper():
        return word.lower()
    if word == word.lower():
        raise OfflineSpellingError(f"the attribute name '{word}' has no off-line spelling (off-line `{word}=` means {word.upper()})")
    return word


def clause_text(clause: n.Clause) -> str:
    """One motion clause; an attribute on a continuation line starts with `with`."""
    if isinstance(clause, n.To):
        return f"to {expression(clause.target)}"
    if isinstance(clause, n.Along):
        return f"along {expression(clause.path)}"
    if isinstance(clause, n.Via):
        return "via " + ", ".join(expression(p) for p in clause.points)
    if isinstance(clause, n.With):
        head = "with " if clause.new_line else ""
        return f"{head}{attribute_name(clause.name)}={expression(clause.value)}"
    if isinstance(clause, n.Until):
        return f"until {expression(clause.condition)}"
    raise TypeError(f"not a clause: {clause!r}")


def _comment(text: str | None) -> str:
    return "" if text is None else f"  #{text}"


def _head_and_clauses(stmt: n.Motion) -> tuple[str, tuple[n.Clause, ...]]:
    """`moveto p` for MOVE ARM TO p; otherwise the keyword and the tool."""
    first = stmt.clauses[0] if stmt.clauses else None
    if stmt.keyword == "MOVE" and stmt.tool.id == "ARM" and isinstance(first, n.To):
        return f"moveto {expression(first.target)}", stmt.clauses[1:]
    return f"{stmt.keyword.lower()} {stmt.tool.id}", stmt.clauses


def simple_statement(stmt: n.Statement) -> str:
    """A one-line statement without its comment (continuation lines of a motion are not included)."""
    if isinstance(stmt, n.Declaration):
        frame = f" in {stmt.frame.id}" if stmt.frame is not None else ""
        return f"{stmt.kind.lower()} {stmt.name.id} = {expression(stmt.value)}{frame}"
    if isinstance(stmt, n.EnumDecl):
        return f"enum {stmt.name.id} = " + ", ".join(m.id for m in stmt.members)
    if isinstance(stmt, n.Assign):
        return f"{expression(stmt.target)} = {expression(stmt.value)}"
    if isinstance(stmt, n.CallStatement):
        return expression(stmt.call)
    if isinstance(stmt, n.Wait):
        return f"wait {expression(stmt.duration)}"
    if isinstance(stmt, n.WaitUntil):
        timeout = f" timeout {expression(stmt.timeout)}" if stmt.timeout is not None else ""
        return f"wait until {expression(stmt.condition)}{timeout}"
    if isinstance(stmt, n.Print):
        return "print(" + ", ".join(expression(v) for v in stmt.values) + ")"
    if isinstance(stmt, n.Raise):
        return f"raise {stmt.name.id}"
    if isinstance(stmt, n.Return):
        return "return" + (f" {expression(stmt.value)}" if stmt.value is not None else "")
    if isinstance(stmt, n.Stop):
        return "stop"
    raise TypeError(f"not a one-line statement: {type(stmt).__name__}")


class _Writer:
    """Collects output lines; blank lines that end a block keep the block's indentation so they stay inside it."""

    def __init__(self) -> None:
        self.lines: list[str] = []

    def line(self, depth: int, text: str, comment: str | None = None) -> None:
        self.lines.append(INDENT * depth + text + _comment(comment))

    def body(self, statements: n.Body, depth: int) -> None:
        trailing = len(statements)
        while trailing > 0 and isinstance(statements[trailing - 1], n.Blank):
            trailing -= 1
        for i, stmt in enumerate(statements):
            if isinstance(stmt, n.Blank):
                self.lines.append(INDENT * depth if i >= trailing and depth > 0 else "")
            else:
                self.statement(stmt, depth)

    def clauses(self, depth: int, head: str, clauses: tuple[n.Clause, ...], comment: str | None) -> None:
        text = head
        for clause in clauses:
            if clause.new_line:
                self.line(depth, text, clause.line_comment)
                for between in clause.comments_before:
                    self.lines.append(INDENT * depth + INDENT + "#" + between)
                text = INDENT + clause_text(clause)
            else:
                text += " " + clause_text(clause)
        self.line(depth, text, comment)

    def inline(self, depth: int, head: str, stmt: n.Statement | None, comment: str | None) -> None:
        """A header line that may carry a statement (`Bolt: moveto bin`)."""
        if isinstance(stmt, n.Motion):
            text, clauses = _head_and_clauses(stmt)
            self.clauses(depth, f"{head} {text}", clauses, comment)
        elif isinstance(stmt, n.Install):
            self.clauses(depth, f"{head} install {stmt.name.id} as {stmt.kind.id}", stmt.attributes, comment)
        else:
            self.line(depth, head + (" " + simple_statement(stmt) if stmt is not None else ""), comment)

    def end(self, depth: int, comment: str | None) -> None:
        """The comment of the on-line closing keyword, on an explicit `end` line."""
        if comment is not None:
            self.line(depth, "end", comment)

    def statement(self, stmt: n.Statement, depth: int) -> None:
        if isinstance(stmt, n.Comment):
            self.lines.append(INDENT * depth + "#" + stmt.text)
        elif isinstance(stmt, n.Motion):
            text, clauses = _head_and_clauses(stmt)
            self.clauses(depth, text, clauses, stmt.comment)
        elif isinstance(stmt, n.Install):
            self.clauses(depth, f"install {stmt.name.id} as {stmt.kind.id}", stmt.attributes, stmt.comment)
        elif isinstance(stmt, n.If):
            for i, branch in enumerate(stmt.branches):
                self.line(depth, f"{'if' if i == 0 else 'elif'} {expression(branch.condition)}:", branch.header_comment)
                self.body(branch.body, depth + 1)
            if stmt.else_body is not None:
                self.line(depth, "else:", stmt.else_comment)
                self.body(stmt.else_body, depth + 1)
            self.end(depth, stmt.comment)
        elif isinstance(stmt, n.While):
            self.block(depth, f"while {expression(stmt.condition)}:", stmt.header_comment, stmt.body, stmt.comment)
        elif isinstance(stmt, n.For):
            step = f" step {expression(stmt.step)}" if stmt.step is not None else ""
            head = f"for {stmt.variable.id} in {expression(stmt.start)}..{expression(stmt.stop)}{step}:"
            self.block(depth, head, stmt.header_comment, stmt.body, stmt.comment)
        elif isinstance(stmt, n.Case):
            self.line(depth, f"case {expression(stmt.subject)}:", stmt.header_comment)
            self.body(stmt.leading, depth + 1)
            for arm in stmt.arms:
                labels = ", ".join(expression(label) for label in arm.labels)
                self.inline(depth + 1, f"{labels}:", arm.inline, arm.header_comment)
                self.body(arm.body, depth + 2)
            if stmt.else_arm is not None:
                self.inline(depth + 1, "else:", stmt.else_arm.inline, stmt.else_arm.header_comment)
                self.body(stmt.else_arm.body, depth + 2)
            self.end(depth, stmt.comment)
        elif isinstance(stmt, n.FrameBlock):
            self.block(depth, f"frame {stmt.frame.id}:", stmt.header_comment, stmt.body, stmt.comment)
        elif isinstance(stmt, n.Try):
            self.line(depth, "try:", stmt.header_comment)
            self.body(stmt.body, depth + 1)
            for handler in stmt.handlers:
                self.inline(depth, f"except {', '.join(h.id for h in handler.names)}:", handler.inline, handler.header_comment)
                self.body(handler.body, depth + 1)
            self.end(depth, stmt.comment)
        elif isinstance(stmt, n.Routine):
            keyword = "def" if stmt.kind == "PROC" else "func"
            params = "(" + ", ".join(p.id for p in stmt.params) + ")" if stmt.parenthesized or stmt.params else ""
            self.block(depth, f"{keyword} {stmt.name.id}{params}:", stmt.header_comment, stmt.body, stmt.comment)
        else:
            self.line(depth, simple_statement(stmt), getattr(stmt, "comment", None))

    def block(self, depth: int, head: str, header_comment: str | None, body: n.Body, comment: str | None) -> None:
        self.line(depth, head, header_comment)
        self.body(body, depth + 1)
        self.end(depth, comment)


def print_offline_statement(stmt: n.Statement, depth: int = 0) -> str:
    """Canonical off-line text of one statement, newline-terminated."""
    writer = _Writer()
    writer.statement(stmt, depth)
    return "\n".join(writer.lines) + "\n"


def check_spellable(program: n.Program) -> None:
    """Refuse names that are off-line keywords (`VAR to = 1` on-line): their off-line text would not read back."""
    from orc_rpl.syntax.offline_builder import OFFLINE_KEYWORDS

    fields = {id(node.name) for node in program.walk() if isinstance(node, n.Field)}
    for node in program.walk():
        if isinstance(node, n.Name) and node.id in OFFLINE_KEYWORDS and id(node) not in fields:
            where = f" (line {node.span.line})" if node.span.line else ""
            raise OfflineSpellingError(f"the name '{node.id}'{where} is an off-line keyword; rename it to convert the program")


def print_offline(program: n.Program) -> str:
    """Canonical off-line text of a whole program (OfflineSpellingError for a tree the syntax cannot spell)."""
    check_spellable(program)
    writer = _Writer()
    writer.body(program.body, 0)
    return "\n".join(writer.lines) + "\n" if writer.lines else ""
