"""`:` command parsing and its errors, the Pygments lexer for RPL, and completion at the command line."""

from __future__ import annotations

import pytest
from pygments.token import Comment, Keyword, Name, Number

from orc_rpl.pendant.commands import COMMANDS, run_line
from orc_rpl.pendant.completion import candidates
from orc_rpl.pendant.lexer import RplLexer
from tests.pendant.support import LINE_MOVE_POS1, session_on


@pytest.mark.parametrize("line, message", [
    (":jgo world x +1mm", "unknown command :jgo; did you mean :jog?"),
    (":jog world x", ":jog: wrong number of arguments; usage: :jog SPACE AXIS AMOUNT"),
    (":jog frame x +1mm", ":jog frame: expected :jog frame NAME AXIS AMOUNT"),
    (":override fast", ":override: expected a percentage such as 50%, got 'fast'"),
    (":override 150%", ":override must be above 0% and at most 100%, got 150%"),
    (":goto ten", ":goto: expected a line number, got 'ten'"),
    (":teach", ":teach: wrong number of arguments; usage: :teach NAME"),
    (":mode turbo", ":mode: expected manual or auto, got 'turbo'"),
    (":shift left", ":shift: expected up or down, got 'left'"),
    (":io DigIn[3]", ":io: expected :io, or :io CHANNEL VALUE"),
    (":help NOPE", ":help: nothing is called 'NOPE'"),
], ids=lambda value: value if value.startswith(":") else None)
def test_command_errors_name_the_command_and_the_argument(tmp_path, line, message) -> None:
    outcome = run_line(session_on(tmp_path), line)
    assert outcome.error and message in outcome.text


def test_typed_statements_and_commands_share_the_command_line(tmp_path) -> None:
    session = session_on(tmp_path)
    assert run_line(session, "PRINT 1 + 1").text.startswith("2")
    assert run_line(session, "MOVE ARM TO").error
    assert run_line(session, ":override 50%").text == "speed override 50%"
    assert run_line(session, ":insert WAIT 1s").text.startswith("inserted at line")
    outcome = run_line(session, ":quit")
    assert outcome.error and ":save first" in outcome.text
    assert run_line(session, ":quit!").quit


def test_every_command_has_usage_and_help(tmp_path) -> None:
    session = session_on(tmp_path)
    for name, command in COMMANDS.items():
        assert command.usage.startswith(name) and command.doc
        assert command.doc in session.panels.help(name)


def _tokens(text: str) -> list[tuple[object, str]]:
    return [(t, v) for t, v in RplLexer().get_tokens(text) if v.strip()]


def test_lexer_highlights_motion_keywords_units_and_comments() -> None:
    tokens = _tokens("GRINDMOVE grinder ALONG edge WITH SPEED = 100mm/s  -- slow\n")
    assert tokens[0] == (Keyword.Reserved, "GRINDMOVE")
    assert (Keyword, "ALONG") in tokens and (Number, "100") in tokens and (Keyword.Type, "mm/s") in tokens
    assert tokens[-1] == (Comment.Single, "-- slow")
    assert (Name.Builtin, "ARM") in _tokens("MOVE ARM TO p")
    assert (Keyword.Pseudo, "teach") in _tokens(":teach p1")


def test_lexer_is_found_by_pygments_for_rpl_files() -> None:
    from pygments.lexers import get_lexer_for_filename
    from pygments.util import ClassNotFound

    try:
        lexer = get_lexer_for_filename("cell.rpl")
    except ClassNotFound:
        pytest.skip("the pygments.lexers entry point is not installed yet (pyproject.toml)")
    assert type(lexer).__name__ == "RplLexer"


@pytest.mark.parametrize("before, expected", [
    (":te", ["teach"]),
    (":", sorted(COMMANDS)),
    (":modpos po", ["pos0", "pos1", "pos2", "pos3"]),
    (":wrap FRAME ba", ["base_plate"]),
    (":mode m", ["manual"]),
    ("MOVE ARM TO pos", ["pos0", "pos1", "pos2", "pos3"]),
    ("MOVE ARM TO p WITH SP", ["SPEED"]),
    ("GRINDMOVE g TO p WITH FO", ["FORCE"]),
    ("LMO", ["LMOVE"]),
    ("ENDF", ["ENDFOR", "ENDFRAME", "ENDFUNC"]),
], ids=lambda value: value if isinstance(value, str) else None)
def test_completion_offers_commands_keywords_attributes_and_names(tmp_path, before, expected) -> None:
    session = session_on(tmp_path)
    session.editor.goto(LINE_MOVE_POS1)
    assert candidates(session, before)[1] == expected
