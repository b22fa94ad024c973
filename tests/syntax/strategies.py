"""Hypothesis strategies for syntax trees in canonical form (they print and re-parse to themselves)."""

from __future__ import annotations

import dataclasses

from hypothesis import strategies as st

from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.lexicon import is_reserved

NAMES = st.from_regex(r"[a-z][a-zA-Z0-9_]{0,6}", fullmatch=True).filter(lambda s: not is_reserved(s))
UPPER_NAMES = st.from_regex(r"[A-Z][A-Z_]{0,5}", fullmatch=True).filter(lambda s: not is_reserved(s))
NUMBER_TEXT = st.one_of(
    st.integers(0, 10_000).map(str),
    st.from_regex(r"[0-9]{1,3}\.[0-9]{1,3}", fullmatch=True),
    st.tuples(st.integers(0, 999), st.sampled_from(["mm", "deg", "ms", "s", "N", "mm/s", "mps", "%", "kg", "m/s2"])).map(
        lambda t: f"{t[0]}{t[1]}"),
)
COMMENT_TEXT = st.one_of(st.none(), st.text(st.characters(min_codepoint=32, max_codepoint=126), max_size=12)
                         .map(lambda s: (" " + s).rstrip()))

name = NAMES.map(n.Name)


def atoms() -> st.SearchStrategy[n.Expression]:
    return st.one_of(
        NUMBER_TEXT.map(n.Number),
        name,
        st.booleans().map(n.Boolean),
        st.text(st.characters(min_codepoint=32, max_codepoint=126), max_size=8).map(n.String),
    )


def _extend(children: st.SearchStrategy[n.Expression]) -> st.SearchStrategy[n.Expression]:
    ops = ["+", "-", "*", "/", "=", "<>", "<", "<=", ">", ">=", "AND", "OR"]
    return st.one_of(
        st.builds(n.Binary, st.sampled_from(ops), children, children),
        st.builds(n.Unary, st.sampled_from(["-", "NOT"]), children),
        st.builds(n.Field, children, name),
        st.builds(n.Index, children, children),
        st.builds(n.Call, children, st.lists(st.builds(n.Argument, st.one_of(st.none(), name), children), max_size=3).map(tuple)),
        st.lists(children, max_size=3).map(tuple).map(n.ListExpr),
    )


expressions = st.recursive(atoms(), _extend, max_leaves=8)


def _clause(first: bool) -> st.SearchStrategy[n.Clause]:
    new_line = st.booleans()

    def flagged(cls: type, *fields: st.SearchStrategy) -> st.SearchStrategy:
        return st.tuples(new_line, COMMENT_TEXT, *fields).map(
            lambda t: cls(*t[2:], new_line=t[0], line_comment=t[1] if t[0] else None))

    return st.one_of(
        st.builds(n.To, expressions),
        st.builds(n.Along, expressions),
        flagged(n.Via, st.lists(expressions, min_size=1, max_size=2).map(tuple)),
        flagged(n.With, UPPER_NAMES.map(n.Name), expressions),
        flagged(n.Until, expressions),
    )


motions = st.builds(
    n.Motion,
    st.sampled_from(["MOVE", "LMOVE", "GRINDMOVE", "WELDMOVE"]),
    name,
    st.lists(_clause(False), min_size=1, max_size=4).map(tuple),
    COMMENT_TEXT,
)

simple_statements = st.one_of(
    st.builds(n.Declaration, st.sampled_from(["TOOL", "POS", "PATH", "CONST", "VAR", "FRAME"]), name, expressions,
              st.one_of(st.none(), name), COMMENT_TEXT),
    st.builds(n.Assign, st.one_of(name, st.builds(n.Index, name, expressions), st.builds(n.Field, name, name)), expressions,
              COMMENT_TEXT),
    st.builds(n.CallStatement, st.one_of(name, st.builds(n.Field, name, name),
                                         st.builds(n.Call, name, st.lists(st.builds(n.Argument, st.none(), expressions),
                                                                          max_size=2).map(tuple))), COMMENT_TEXT),
    motions,
    st.builds(n.Print, st.lists(expressions, max_size=3).map(tuple), COMMENT_TEXT),
    st.builds(n.Wait, expressions, COMMENT_TEXT),
    st.builds(n.WaitUntil, expressions, st.one_of(st.none(), expressions), COMMENT_TEXT),
    st.builds(n.Raise, name, COMMENT_TEXT),
    st.builds(n.Return, st.one_of(st.none(), expressions), COMMENT_TEXT),
    st.builds(n.Stop, COMMENT_TEXT),
    st.builds(n.EnumDecl, name, st.lists(name, min_size=1, max_size=3).map(tuple), COMMENT_TEXT),
)

lines = st.one_of(simple_statements, COMMENT_TEXT.filter(lambda c: c is not None).map(n.Comment), st.just(n.Blank()))
labels = st.one_of(NUMBER_TEXT.map(n.Number), name, st.booleans().map(n.Boolean),
                   st.integers(1, 99).map(lambda i: n.Unary("-", n.Number(str(i)))))


def _compound(body: st.SearchStrategy[tuple]) -> st.SearchStrategy[n.Statement]:
    # The comment of a label line belongs to the arm (header_comment), not to its inline statement.
    inline = st.one_of(st.none(), simple_statements.map(lambda s: dataclasses.replace(s, comment=None)))
    return st.one_of(
        st.builds(lambda branches, else_body, else_comment, comment: n.If(
            branches, else_body, else_comment if else_body is not None else None, comment),
            st.lists(st.builds(n.Branch, expressions, body, COMMENT_TEXT), min_size=1, max_size=2).map(tuple),
            st.one_of(st.none(), body), COMMENT_TEXT, COMMENT_TEXT),
        st.builds(n.While, expressions, body, COMMENT_TEXT, COMMENT_TEXT),
        st.builds(n.For, name, expressions, expressions, st.one_of(st.none(), expressions), body, COMMENT_TEXT, COMMENT_TEXT),
        st.builds(n.FrameBlock, name, body, COMMENT_TEXT, COMMENT_TEXT),
        st.builds(n.Case, expressions,
                  st.lists(st.builds(n.CaseArm, st.lists(labels, min_size=1, max_size=2).map(tuple), inline, body, COMMENT_TEXT),
                           max_size=2).map(tuple),
                  st.one_of(st.none(), st.builds(n.CaseArm, st.just(()), inline, body, COMMENT_TEXT)),
                  COMMENT_TEXT, st.lists(st.one_of(st.just(n.Blank()), COMMENT_TEXT.filter(bool).map(n.Comment)),
                                         max_size=1).map(tuple), COMMENT_TEXT),
        st.builds(n.Try, body, st.lists(st.builds(n.Handler, st.lists(name, min_size=1, max_size=2).map(tuple), inline, body,
                                                  COMMENT_TEXT), min_size=1, max_size=2).map(tuple), COMMENT_TEXT, COMMENT_TEXT),
    )


bodies = st.recursive(st.lists(lines, max_size=3).map(tuple),
                      lambda inner: st.lists(st.one_of(lines, _compound(inner)), max_size=3).map(tuple), max_leaves=6)

routines = st.builds(n.Routine, st.sampled_from(["PROC", "FUNC"]), name, st.lists(name, max_size=2).map(tuple), bodies,
                     st.just(True), COMMENT_TEXT, COMMENT_TEXT)

programs = st.lists(st.one_of(lines, _compound(bodies), routines), max_size=6).map(tuple).map(n.Program)
