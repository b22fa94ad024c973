"""Comment lines the off-line syntax accepts where Python does: before `else:` at the `if`'s indentation, and between a
motion and its continuation lines (both syntaxes); they stay in the tree and print back stably."""

from __future__ import annotations

import pytest

from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.offline_parser import parse_offline
from orc_rpl.syntax.offline_printer import print_offline
from orc_rpl.syntax.parser import parse
from orc_rpl.syntax.printer import print_program

BEFORE_ELSE = 'if x > 0:\n    print("a")\n# about the else\nelse:\n    print("b")\n'


def test_a_comment_before_else_at_the_if_indentation_parses_into_the_block_above() -> None:
    program = parse_offline(BEFORE_ELSE, "p.orl")
    (stmt,) = program.body
    assert isinstance(stmt, n.If)
    assert stmt.branches[0].body[-1] == n.Comment(" about the else")
    canonical = print_offline(program)
    assert canonical == 'if x > 0:\n    print("a")\n    # about the else\nelse:\n    print("b")\n'
    assert parse_offline(canonical, "p.orl") == program


@pytest.mark.parametrize("text, parser, printer", [
    ("MOVE ARM TO p  -- first\n  -- between\n  -- and more\n  WITH SPEED = 0.1mps\n", parse, print_program),
    ("moveto p  # first\n    # between\n    with speed=0.1mps\n", parse_offline, print_offline),
], ids=["online", "offline"])
def test_comment_lines_between_a_motion_and_its_continuation_are_kept(text, parser, printer) -> None:  # type: ignore[no-untyped-def]
    program = parser(text, "p")
    (motion,) = program.body
    clause = motion.clauses[-1]
    assert clause.new_line and clause.line_comment == " first" and clause.comments_before[0] == " between"
    assert printer(program) == text


def test_a_comment_indented_deeper_than_the_closing_keyword_stays_where_its_indentation_reaches() -> None:
    # found by the generated round trip: a comment at the else-body's indentation after a nested block
    text = "case 0:\n    else:\n        frame a:\n            tool b = []\n        #\nend  # done\n"
    program = parse_offline(text, "p.orl")
    (case,) = program.body
    body = case.else_arm.body
    assert isinstance(body[0], n.FrameBlock) and body[-1] == n.Comment("")
    assert print_offline(program) == text
