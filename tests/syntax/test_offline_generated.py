"""Hypothesis: generated trees print off-line and re-parse equal; arbitrary off-line-like text fails only with SourceError."""

from __future__ import annotations

import os

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from orc_rpl.errors import SourceError
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.offline_builder import OFFLINE_KEYWORDS
from orc_rpl.syntax.offline_parser import parse_offline
from orc_rpl.syntax.offline_printer import print_offline
from orc_rpl.syntax.parser import parse
from orc_rpl.syntax.printer import print_program
from tests.syntax.strategies import programs


def offline_spellable(program: n.Program) -> bool:
    """Trees whose names are not off-line keywords (those names have no off-line spelling)."""
    return not any(isinstance(node, n.Name) and node.id in OFFLINE_KEYWORDS for node in program.walk())


#: ORC_HYPOTHESIS_EXAMPLES=N runs N examples of each test instead of the default.
EXAMPLES = os.environ.get("ORC_HYPOTHESIS_EXAMPLES")

ORL_ALPHABET = st.sampled_from(list("movetowithifelsecasefor abcxyz0123456789_=<>+-*/()[],.:\"\n\t%#")
                               + ["moveto ", "if ", ":\n    ", "\n", "\n    ", "# c", "with ", "\n    with ", "frame ",
                                  "for i in 1..3:\n", "def f():\n", "end\n", "  "])


@settings(max_examples=int(EXAMPLES or 400), deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(programs.filter(offline_spellable))
def test_generated_trees_print_offline_and_reparse_equal(program: n.Program) -> None:
    text = print_offline(program)
    reparsed = parse_offline(text, "generated.orl")
    assert reparsed == program, text
    assert print_offline(reparsed) == text
    assert parse(print_program(reparsed)) == program


@settings(max_examples=int(EXAMPLES or 300), deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(ORL_ALPHABET, max_size=40).map("".join))
def test_arbitrary_orl_like_text_raises_only_source_error(text: str) -> None:
    try:
        tree = parse_offline(text, "fuzz.orl")
    except SourceError as error:
        for diagnostic in error.diagnostics:
            assert diagnostic.location.line >= 1 and diagnostic.location.column >= 1
            assert diagnostic.location.path == "fuzz.orl"
        return
    assert isinstance(tree, n.Program)
    assert parse_offline(print_offline(tree)) == tree
