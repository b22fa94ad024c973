"""Structured edits through the syntax tree never leave the program unparsable or off its canonical form."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from orc_rpl.pendant.robot import PendantRobot
from orc_rpl.pendant.session import PendantSession
from orc_rpl.pendant.tree import EditError, stops
from orc_rpl.syntax.parser import parse
from orc_rpl.syntax.printer import print_program
from tests.pendant.support import FRAME_PROGRAM

STATEMENTS = ["WAIT 1s", "MOVE ARM TO pos0", "PRINT \"x\"", "IF TRUE THEN\n    WAIT 1s\nENDIF",
              "FRAME base_plate\n    MOVE ARM TO pos1\nENDFRAME", "-- a comment", "ENDFRAME", "MOVE ARM TO"]
EDITS = st.lists(st.tuples(st.sampled_from(["insert", "delete", "wrap", "up", "down", "replace", "undo", "select"]),
                           st.integers(0, 60), st.sampled_from(STATEMENTS)), min_size=1, max_size=12)


def _apply(session: PendantSession, edit: str, where: int, text: str) -> None:
    session.editor.cursor = where % len(session.editor.stops) if session.editor.stops else 0
    actions = {"insert": lambda: session.editor.insert(text), "delete": session.editor.delete,
               "wrap": lambda: session.editor.wrap("base_plate"), "up": lambda: session.editor.shift("up"),
               "down": lambda: session.editor.shift("down"), "replace": lambda: session.editor.replace(text),
               "undo": session.editor.undo, "select": session.editor.select}
    actions[edit]()


@settings(max_examples=40, deadline=None)
@given(EDITS)
def test_any_sequence_of_edits_keeps_the_program_parsable_and_canonical(edits) -> None:
    session = PendantSession("edits.rpl", text=FRAME_PROGRAM, robot=PendantRobot.virtual(backend="kinematic"),
                             journal=False)
    for edit, where, text in edits:
        before = session.editor.text
        try:
            _apply(session, edit, where, text)
        except EditError:
            assert session.editor.text == before  # a refused edit changes nothing
        program = parse(session.editor.text)
        assert print_program(program) == session.editor.text
        assert [s.line for s in stops(program)] == [s.line for s in session.editor.stops]
