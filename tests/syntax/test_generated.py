"""Hypothesis: arbitrary text fails only with the project's error; generated trees print and re-parse equal."""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from orc_rpl.errors import SourceError
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.parser import parse
from orc_rpl.syntax.printer import print_program
from tests.syntax.strategies import programs

RPL_ALPHABET = st.sampled_from(list("MOVETOWITHIFENDFRAMEVIAUNTILCASEOF abcxyz0123456789_=<>+-*/()[],.:\"\n\t%-")
                               + ["MOVE ", "IF ", " THEN\n", "ENDIF\n", "--", "WITH ", "\n  WITH ", "FRAME ", "ENDFRAME\n"])


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(RPL_ALPHABET, max_size=40).map("".join))
def test_arbitrary_rpl_like_text_raises_only_source_error(text: str) -> None:
    try:
        tree = parse(text, "fuzz.rpl")
    except SourceError as error:
        for diagnostic in error.diagnostics:
            assert diagnostic.location.line >= 1 and diagnostic.location.column >= 1
            assert diagnostic.location.path == "fuzz.rpl"
        return
    assert isinstance(tree, n.Program)
    assert parse(print_program(tree)) == tree


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.text(max_size=60))
def test_arbitrary_unicode_raises_only_source_error(text: str) -> None:
    try:
        parse(text)
    except SourceError:
        pass


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(programs)
def test_generated_trees_print_and_reparse_equal(program: n.Program) -> None:
    text = print_program(program)
    reparsed = parse(text, "generated.rpl")
    assert reparsed == program, text
    assert print_program(reparsed) == text
