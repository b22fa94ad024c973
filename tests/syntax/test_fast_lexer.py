"""The fast lexer and the fast LALR loop give exactly what Lark gives: the same trees and spans, the same errors."""

from __future__ import annotations

from pathlib import Path

import pytest
from lark import Lark
from lark.exceptions import UnexpectedInput

from orc_rpl.syntax.builder import BuildError, TreeBuilder
from orc_rpl.syntax.fast_lexer import FastContextualLexer, speed_up
from orc_rpl.syntax.grammar_files import grammar_path
from orc_rpl.syntax.lalr import FastLalr
from orc_rpl.syntax.limits import nesting_problem

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
    monkeypatch.setattr(offline_parser, "_parse_once", lambda: plain.parse)
    expected = offline_parser.parse_offline(text, "p.orl")
    assert not isinstance(plain.parser.lexer.lexer, FastContextualLexer)
    assert fast == expected
    assert [n.span for n in fast.walk()] == [n.span for n in expected.walk()]


# ---- the LALR loop of orc_rpl.syntax.lalr on the same tables, against Lark's own loop

def _same_outcome(parse_fast, parse_lark, text: str) -> None:  # type: ignore[no-untyped-def]
    try:
        expected = parse_lark(text)
    except Exception as error:
        with pytest.raises(type(error)) as raised:
            parse_fast(text)
        assert _described(raised.value) == _described(error)
        return
    got = parse_fast(text)
    if nesting_problem(expected) is not None:  # deeper than == can compare: the same depth, at the same place
        assert nesting_problem(got) == nesting_problem(expected)
        return
    assert got == expected
    assert [n.span for n in got.walk()] == [n.span for n in expected.walk()]


FAST_LOOP = FastLalr(FAST)


def test_the_fast_loop_is_in_use() -> None:
    from orc_rpl.syntax import offline_parser, parser

    assert parser._parse_once().__self__.__class__ is FastLalr
    assert offline_parser._parse_once().__self__.__class__ is FastLalr


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: str(p.relative_to(ROOT)))
def test_fast_loop_same_tree_and_spans_as_lark(program: Path) -> None:
    _same_outcome(FAST_LOOP.parse, LARK.parse, program.read_text())


@pytest.mark.parametrize("text", BROKEN)
def test_fast_loop_same_outcome_for_odd_input(text: str) -> None:
    _same_outcome(FAST_LOOP.parse, LARK.parse, text)


def test_fast_loop_same_outcome_for_hostile_programs() -> None:
    import random

    from tests import fuzz_inputs

    rng = random.Random(11)
    for _ in range(300):
        suffix, text = fuzz_inputs.program(rng)
        if suffix == ".rpl":
            _same_outcome(FAST_LOOP.parse, LARK.parse, text)


def test_fast_loop_same_offline_outcome_for_hostile_programs() -> None:
    import random

    from orc_rpl.syntax.offline_builder import OfflineTreeBuilder
    from orc_rpl.syntax.offline_lexer import OfflinePostLexer, plan_indentation
    from orc_rpl.syntax.parser import source_lines
    from tests import fuzz_inputs

    postlexer = OfflinePostLexer()
    plain = Lark(grammar_path("orl.lark").read_text(), parser="lalr", lexer="contextual", start="program",
                 maybe_placeholders=True, postlex=postlexer, transformer=OfflineTreeBuilder())
    fast = FastLalr(speed_up(Lark(grammar_path("orl.lark").read_text(), parser="lalr", lexer="contextual", start="program",
                                  maybe_placeholders=True, postlex=postlexer, transformer=OfflineTreeBuilder())))
    rng = random.Random(12)
    texts = [p.read_text() for p in OFFLINE]
    for _ in range(300):
        suffix, text = fuzz_inputs.program(rng)
        texts.append(text if suffix == ".orl" else "\n".join(line.lower() for line in text.splitlines()))
    for text in texts:
        lines = source_lines(text)
        plan = plan_indentation(lines)
        if plan.problems:
            continue
        source = "\n".join(lines) + "\n" if lines else ""

        def planned(parse):  # type: ignore[no-untyped-def]
            def run(text: str):  # type: ignore[no-untyped-def]
                postlexer.plan = plan
                return parse(text)
            return run
        _same_outcome(planned(fast.parse), planned(plain.parse), source)


# ---- the analysed parsers kept between runs


def test_the_parser_cache_is_used_and_a_broken_one_is_analysed_again(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from orc_rpl.syntax import parser
    from orc_rpl.syntax.grammar_files import parser_cache

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    cache = Path(parser_cache("rpl"))  # type: ignore[arg-type]
    assert cache.parent == tmp_path / "orc_rpl"
    text = "MOVE ARM TO p WITH SPEED = 0.5 * Vmax\n"
    first = FastLalr(parser._lark.__wrapped__()).parse(text)
    assert cache.is_file()
    whole = cache.read_bytes()
    cache.write_bytes(whole[: len(whole) // 2])  # half-written (a crash, or another process writing it)
    assert FastLalr(parser._lark.__wrapped__()).parse(text) == first
    assert len(cache.read_bytes()) > 0.9 * len(whole)  # analysed again and written whole again


def test_without_a_cache_folder_the_grammar_is_analysed_each_time(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from orc_rpl.syntax import parser
    from orc_rpl.syntax.grammar_files import parser_cache

    blocker = tmp_path / "not-a-folder"
    blocker.write_text("")
    monkeypatch.setenv("XDG_CACHE_HOME", str(blocker))
    assert parser_cache("rpl") is False
    assert FastLalr(parser._lark.__wrapped__()).parse("x = 1\n") == LARK.parse("x = 1\n")
