"""The fast lexer gives exactly what Lark's contextual lexer gives: the same trees and spans, the same errors."""

from __future__ import annotations

from pathlib import Path

import pytest
from lark import Lark
from lark.exceptions import UnexpectedInput

from orc_rpl.syntax.builder import BuildError, TreeBuilder
from orc_rpl.syntax.fast_lexer import FastContextualLexer, speed_up
from orc_rpl.syntax.grammar_files import grammar_path

ROOT = Path(__file__).resolve().parent.parent.parent
PROGRAMS = sorted([*ROOT.glob("programs/online/*.rpl"), *ROOT.glob("tests/**/*.rpl")])


def _parser() -> Lark:
    return Lark(grammar_path("rpl.lark").read_text(), parser="lalr", lexer="contextual", start="program",
                maybe_placeholders=True, transformer=TreeBuilder())


LARK, FAST = _parser(), speed_up(_parser())


def _described(error: BaseException) -> tuple[object, ...]:
    """An error as the user reads it: where, what was found, what was expected (a set: Lark lists it in any order)."""
    expected = getattr(error, "expected", None) or getattr(error, "allowed", None) or ()
    return (type(error), getattr(error, "line", None), getattr(error, "column", None),
            str(getattr(error, "token", "")), sorted(expected), str(error).split("Expected", 1)[0])


def test_the_fast_lexer_is_in_use() -> None:
    assert isinstance(FAST.parser.lexer, FastContextualLexer)


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: str(p.relative_to(ROOT)))
def test_same_tree_and_spans_as_lark(program: Path) -> None:
    text = program.read_text()
    try:
        expected = LARK.parse(text)
    except Exception as error:  # a deliberately broken test program: the same error
        with pytest.raises(type(error)) as raised:
            FAST.parse(text)
        assert _described(raised.value) == _described(error)
        return
    got = FAST.parse(text)
    assert got == expected
    assert [n.span for n in got.walk()] == [n.span for n in expected.walk()]


BROKEN = ["VAR IF = 2\n", "MOVE ARM TO\n", "x = 1 +\n", "PRINT \"open\n", "x = 3 $ 4\n", "MOVEE g TO p\n",
          "IF x THEN\nENDWHILE\n", "WITH SPEED = 1\n", "x = (1\n", "FOR i FROM 1 TO DO\nENDFOR\n", "   \t  \n  x = 1  \n",
          "MOVE ARM TO p -- c\n  -- d\n  WITH V = 1\n", "a.TO = 1\n", "CASE x OF\n  1 : PRINT 1\nENDCASE\n"]


@pytest.mark.parametrize("text", BROKEN)
def test_same_outcome_for_odd_input(text: str) -> None:
    try:
        expected = LARK.parse(text)
    except (UnexpectedInput, BuildError) as error:
        with pytest.raises(type(error)) as raised:
            FAST.parse(text)
        assert _described(raised.value) == _described(error)
        if isinstance(error, UnexpectedInput):
            assert (raised.value.line, raised.value.column) == (error.line, error.column)  # type: ignore[union-attr]
        return
    assert FAST.parse(text) == expected


OFFLINE = sorted([*ROOT.glob("programs/offline/*.orl"), *ROOT.glob("tests/**/*.orl")])


@pytest.mark.parametrize("program", OFFLINE, ids=lambda p: str(p.relative_to(ROOT)))
def test_offline_same_tree_and_spans_as_lark(program: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from orc_rpl.syntax import offline_parser
    from orc_rpl.syntax.offline_builder import OfflineTreeBuilder
    from orc_rpl.syntax.offline_lexer import OfflinePostLexer

    text = program.read_text()
    fast = offline_parser.parse_offline(text, "p.orl")
    postlexer = OfflinePostLexer()
    plain = Lark(grammar_path("orl.lark").read_text(), parser="lalr", lexer="contextual", start="program",
                 maybe_placeholders=True, postlex=postlexer, transformer=OfflineTreeBuilder())
    monkeypatch.setattr(offline_parser, "_lark", lambda: (plain, postlexer))
    expected = offline_parser.parse_offline(text, "p.orl")
    assert not isinstance(plain.parser.lexer.lexer, FastContextualLexer)
    assert fast == expected
    assert [n.span for n in fast.walk()] == [n.span for n in expected.walk()]
