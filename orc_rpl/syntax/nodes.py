"""The one syntax tree of both syntaxes: frozen nodes, children in tuples, spans outside equality."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Iterator, Union


@dataclass(frozen=True, slots=True)
class Span:
    """Source position of a node: 1-based line and column; the end is exclusive."""

    line: int = 0
    column: int = 0
    end_line: int = 0
    end_column: int = 0


NO_SPAN = Span()


@dataclass(frozen=True, slots=True)
class Node:
    """Base of every node; `span` travels with the node but never takes part in equality."""

    span: Span = field(default=NO_SPAN, compare=False, repr=False, kw_only=True)

    def children(self) -> Iterator[Node]:
        """Direct child nodes, in source order."""
        for name in self.__dataclass_fields__:
            if name == "span":
                continue
            value = getattr(self, name)
            if isinstance(value, Node):
                yield value
            elif isinstance(value, tuple):
                for item in value:
                    if isinstance(item, Node):
                        yield item

    def walk(self) -> Iterator[Node]:
        """This node and every node below it, depth first, in source order."""
        stack: list[Node] = [self]
        while stack:
            node = stack.pop()
            yield node
            stack.extend(reversed(list(node.children())))


# ---- expressions -------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Expression(Node):
    """Anything that has a value."""


@dataclass(frozen=True, slots=True)
class Number(Expression):
    """A number literal, possibly with a unit: `12`, `0.15`, `100mm/s`, `50%`."""

    text: str                          #: as written; the value in SI comes from units.parse_literal


@dataclass(frozen=True, slots=True)
class String(Expression):
    """A string literal `"text"` (value without quotes, escapes resolved)."""

    value: str


@dataclass(frozen=True, slots=True)
class Boolean(Expression):
    """`TRUE` or `FALSE`."""

    value: bool


@dataclass(frozen=True, slots=True)
class Name(Expression):
    """A name: a variable, position, tool, frame, unit constant, ENUM value, routine..."""

    id: str


@dataclass(frozen=True, slots=True)
class ListExpr(Expression):
    """A list `[a, b, c]`."""

    items: tuple[Expression, ...]


@dataclass(frozen=True, slots=True)
class Field(Expression):
    """`value.name`: a field of a pose or record, or a method or attribute of an installed object."""

    value: Expression
    name: Name


@dataclass(frozen=True, slots=True)
class Index(Expression):
    """`value[index]`: list element (from 1; ENUM values as indices) or an IO channel."""

    value: Expression
    index: Expression


@dataclass(frozen=True, slots=True)
class Argument(Node):
    """One call argument, positional (`name` is None) or `name = value`."""

    name: Name | None
    value: Expression


@dataclass(frozen=True, slots=True)
class Call(Expression):
    """`function(arguments)`."""

    function: Expression
    arguments: tuple[Argument, ...]


@dataclass(frozen=True, slots=True)
class Unary(Expression):
    """`-x`, `+x` or `NOT x`."""

    op: str                            #: "-", "+" or "NOT"
    operand: Expression


@dataclass(frozen=True, slots=True)
class Binary(Expression):
    """`left op right` for arithmetic, comparison and logic."""

    op: str                            #: + - * / = <> < <= > >= AND OR
    left: Expression
    right: Expression


# ---- lines that are not statements -----------------------------------------------


@dataclass(frozen=True, slots=True)
class Statement(Node):
    """Anything that stands on a line of a block; `comment` is the comment ending its (last) line."""


@dataclass(frozen=True, slots=True)
class Comment(Statement):
    """A line holding only a comment (`-- text`); `text` is what follows the dashes."""

    text: str


@dataclass(frozen=True, slots=True)
class Blank(Statement):
    """An empty line, kept so that formatting and transformation keep the program's layout."""


# ---- declarations ----------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Declaration(Statement):
    """`TOOL|FRAME|POS|PATH|CONST|VAR name = value [IN frame]`."""

    kind: str                          #: TOOL, FRAME, POS, PATH, CONST or VAR
    name: Name
    value: Expression
    frame: Name | None = None          #: IN frame: the on-line frame the numbers are relative to
    comment: str | None = None


@dataclass(frozen=True, slots=True)
class EnumDecl(Statement):
    """`ENUM Part = NoObject, Bolt, Nut`: ordered values, the first is 1 as an index."""

    name: Name
    members: tuple[Name, ...]
    comment: str | None = None


# ---- motion ------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Clause(Node):
    """One clause of a motion statement; `new_line` keeps the thesis' continuation-line layout."""

    new_line: bool = field(default=False, kw_only=True)
    line_comment: str | None = field(default=None, kw_only=True)
    #: comment-only lines standing between the line above and this clause's continuation line
    comments_before: tuple[str, ...] = field(default=(), kw_only=True)


@dataclass(frozen=True, slots=True)
class To(Clause):
    """`TO target`."""

    target: Expression


@dataclass(frozen=True, slots=True)
class Along(Clause):
    """`ALONG path`."""

    path: Expression


@dataclass(frozen=True, slots=True)
class Via(Clause):
    """`VIA p, q`: via points passed on the way."""

    points: tuple[Expression, ...]


@dataclass(frozen=True, slots=True)
class With(Clause):
    """`WITH NAME = value`: a motion attribute (or an output binding such as `Id = IDENT(...)`)."""

    name: Name
    value: Expression


@dataclass(frozen=True, slots=True)
class Until(Clause):
    """`UNTIL condition`: stop on the path in the cycle the condition becomes true."""

    condition: Expression


@dataclass(frozen=True, slots=True)
class Motion(Statement):
    """A motion statement: `MOVE grinder TO p WITH SPEED=0.5mps VIA a, b`."""

    keyword: str                       #: MOVE, LMOVE, GRINDMOVE, ... as written
    tool: Name                         #: the tool whose TCP moves
    clauses: tuple[Clause, ...]        #: TO, ALONG, VIA, WITH and UNTIL in source order
    comment: str | None = None

    @property
    def target(self) -> Expression | None:
        """The TO target, if any."""
        return next((c.target for c in self.clauses if isinstance(c, To)), None)

    @property
    def path(self) -> Expression | None:
        """The ALONG path, if any."""
        return next((c.path for c in self.clauses if isinstance(c, Along)), None)

    @property
    def attributes(self) -> tuple[With, ...]:
        """The WITH clauses."""
        return tuple(c for c in self.clauses if isinstance(c, With))


@dataclass(frozen=True, slots=True)
class Install(Statement):
    """`INSTALL name AS Kind WITH ...`: equipment or a sensor of a registered kind."""

    name: Name
    kind: Name
    attributes: tuple[With, ...]       #: WITH clauses (a With may start a continuation line)
    comment: str | None = None


# ---- simple statements ---------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Assign(Statement):
    """`target = value` (also `DigOut[5] = 0`, `rec.field = v`)."""

    target: Expression
    value: Expression
    comment: str | None = None


@dataclass(frozen=True, slots=True)
class CallStatement(Statement):
    """A call used as a statement: `GrinderOff`, `Gripper1.Close`, `Pick(p1)`."""

    call: Expression                   #: a Name, a Field or a Call
    comment: str | None = None


@dataclass(frozen=True, slots=True)
class Wait(Statement):
    """`WAIT 0.5s`."""

    duration: Expression
    comment: str | None = None


@dataclass(frozen=True, slots=True)
class WaitUntil(Statement):
    """`WAIT UNTIL condition [TIMEOUT duration]`; raises Timeout when the time runs out."""

    condition: Expression
    timeout: Expression | None = None
    comment: str | None = None


@dataclass(frozen=True, slots=True)
class Print(Statement):
    """`PRINT a, b`: values on one line of standard output, separated by one space."""

    values: tuple[Expression, ...]
    comment: str | None = None


@dataclass(frozen=True, slots=True)
class Raise(Statement):
    """`RAISE name`: raise a user exception."""

    name: Name
    comment: str | None = None


@dataclass(frozen=True, slots=True)
class Return(Statement):
    """`RETURN [value]`."""

    value: Expression | None = None
    comment: str | None = None


@dataclass(frozen=True, slots=True)
class Stop(Statement):
    """`STOP`: end the program (the robot stops on its path)."""

    comment: str | None = None


# ---- compound statements ---------------------------------------------------------------

Body = tuple[Statement, ...]


@dataclass(frozen=True, slots=True)
class Branch(Node):
    """`IF`/`ELSIF condition THEN` and its block."""

    condition: Expression
    body: Body
    header_comment: str | None = None


@dataclass(frozen=True, slots=True)
class If(Statement):
    """`IF ... THEN ... ELSIF ... ELSE ... ENDIF`."""

    branches: tuple[Branch, ...]       #: the IF branch, then every ELSIF
    else_body: Body | None = None      #: None when there is no ELSE
    else_comment: str | None = None
    comment: str | None = None         #: on the ENDIF line


@dataclass(frozen=True, slots=True)
class While(Statement):
    """`WHILE condition DO ... ENDWHILE`."""

    condition: Expression
    body: Body
    header_comment: str | None = None
    comment: str | None = None


@dataclass(frozen=True, slots=True)
class For(Statement):
    """`FOR i FROM a TO b [STEP c] DO ... ENDFOR` (both bounds included)."""

    variable: Name
    start: Expression
    stop: Expression
    step: Expression | None
    body: Body
    header_comment: str | None = None
    comment: str | None = None


@dataclass(frozen=True, slots=True)
class CaseArm(Node):
    """`label, label : [statement]` and the lines below it."""

    labels: tuple[Expression, ...]     #: empty for the ELSE arm
    inline: Statement | None           #: a statement written on the label line
    body: Body
    header_comment: str | None = None


@dataclass(frozen=True, slots=True)
class Case(Statement):
    """`CASE subject OF arms [ELSE : ...] ENDCASE`."""

    subject: Expression
    arms: tuple[CaseArm, ...]
    else_arm: CaseArm | None = None
    header_comment: str | None = None
    leading: Body = ()                 #: comment and blank lines before the first label
    comment: str | None = None


@dataclass(frozen=True, slots=True)
class FrameBlock(Statement):
    """`FRAME name ... ENDFRAME`: `name` is the on-line frame of every motion inside."""

    frame: Name
    body: Body
    header_comment: str | None = None
    comment: str | None = None


@dataclass(frozen=True, slots=True)
class Handler(Node):
    """`ON name, name : [statement]` and its block."""

    names: tuple[Name, ...]
    inline: Statement | None
    body: Body
    header_comment: str | None = None


@dataclass(frozen=True, slots=True)
class Try(Statement):
    """`TRY ... ON name : ... ENDTRY`."""

    body: Body
    handlers: tuple[Handler, ...]
    header_comment: str | None = None
    comment: str | None = None


@dataclass(frozen=True, slots=True)
class Routine(Statement):
    """`PROC name[(params)] ... ENDPROC` or `FUNC name(params) ... ENDFUNC`."""

    kind: str                          #: PROC or FUNC
    name: Name
    params: tuple[Name, ...]
    body: Body
    parenthesized: bool = True         #: `PROC GrinderOff` is written without parentheses
    header_comment: str | None = None
    comment: str | None = None


@dataclass(frozen=True, slots=True)
class Program(Node):
    """A whole program file: its lines in order."""

    body: Body


AnyNode = Union[Node, Expression, Statement]
