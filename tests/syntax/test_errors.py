"""Syntax errors: golden messages with file, line, column, the source line and a caret; all errors of a file."""

from __future__ import annotations

import pytest

from orc_rpl.errors import SourceError
from orc_rpl.syntax.parser import parse


def errors_of(source: str) -> str:
    with pytest.raises(SourceError) as info:
        parse(source, "prog.rpl")
    return info.value.format()


GOLDEN = [
    (
        "empty list as a statement",  # the list has no element to point at: the brackets are the place
        "x = 1\n[]\n",
        "prog.rpl:2:1: this expression is not a statement; assign it or call something\n"
        "    2 | []\n"
        "      | ^^\n"
        "      = hint: write `x = ...` to keep a value",
    ),
    (
        "motion without TO",
        "MOVE grinder right_edge\n",
        "prog.rpl:1:14: unexpected name 'right_edge'; expected 'ALONG', 'TO', 'UNTIL', 'VIA' or 'WITH'\n"
        "    1 | MOVE grinder right_edge\n"
        "      |              ^^^^^^^^^^",
    ),
    (
        "reserved word as a name",
        "VAR IF = 2\n",
        "prog.rpl:1:5: 'IF' is a reserved word and cannot be used as a name\n"
        "    1 | VAR IF = 2\n"
        "      |     ^^",
    ),
    (
        "motion keyword as a name",
        "VAR LMOVE = 2\n",
        "prog.rpl:1:5: 'LMOVE' is a reserved word and cannot be used as a name\n"
        "    1 | VAR LMOVE = 2\n"
        "      |     ^^^^^",
    ),
    (
        "closer that closes nothing",
        "STOP\nENDIF\n",
        "prog.rpl:2:1: 'ENDIF' closes nothing: no IF block is open\n"
        "    2 | ENDIF\n"
        "      | ^^^^^",
    ),
    (
        "block never closed",
        "WHILE TRUE DO\n    STOP\n",
        "prog.rpl:1:1: WHILE is never closed: expected ENDWHILE before the end of the file\n"
        "    1 | WHILE TRUE DO\n"
        "      | ^^^^^",
    ),
    (
        "wrong closer names the innermost open block",
        "WHILE TRUE DO\n    IF a THEN\n        STOP\nENDWHILE\n",
        "prog.rpl:4:1: 'ENDWHILE' found while IF (line 2) is still open\n"
        "    4 | ENDWHILE\n"
        "      | ^^^^^^^^\n"
        "      = hint: close the IF of line 2 with ENDIF first",
    ),
    (
        "unclosed string",
        'PRINT "abc\n',
        "prog.rpl:1:7: string is not closed before the end of the line\n"
        '    1 | PRINT "abc\n'
        "      |       ^",
    ),
    (
        "continuation after a non-motion",
        "x = 1\n  WITH SPEED = 1\n",
        "prog.rpl:2:3: a line starting with WITH continues only a motion or an INSTALL statement\n"
        "    2 |   WITH SPEED = 1\n"
        "      |   ^^^^",
    ),
]


@pytest.mark.parametrize("source, expected", [c[1:] for c in GOLDEN], ids=[c[0] for c in GOLDEN])
def test_golden_syntax_error(source: str, expected: str) -> None:
    text = errors_of(source)
    assert text.startswith(expected), text


def test_every_bad_line_is_reported_in_one_run() -> None:
    source = "MOVE g\nx = = 1\nSTOP\nPRINT 1 +\nIF a THEN\n    y = )\nENDIF\n"
    error = None
    try:
        parse(source, "prog.rpl")
    except SourceError as e:
        error = e
    assert error is not None
    assert [d.location.line for d in error.diagnostics] == [1, 2, 4, 6]


def test_assigning_to_a_call_is_refused_at_the_call() -> None:
    text = errors_of("f(1) = 2\n")
    assert text.startswith("prog.rpl:1:1: only a name, a field or an indexed element can be assigned")
