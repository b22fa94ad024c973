"""Pendant edits keep the layout of the statements they do not touch (the program text is the user's)."""

from __future__ import annotations

from orc_rpl.pendant.robot import PendantRobot
from orc_rpl.pendant.session import PendantSession

ODD = """\
-- typed by hand, aligned
VAR   n = 0            -- counter
POS p1 = POSE(800mm,-300mm,900mm,0,180deg,0)
MOVE ARM TO p1   WITH SPEED = 0.5*1.5mps
WHILE n<3 DO
  n=n+1
  WAIT 0.1s
ENDWHILE
PRINT   "done"
"""


def _session() -> PendantSession:
    return PendantSession("odd.rpl", text=ODD, robot=PendantRobot.virtual(backend="kinematic"), journal=False)


def test_replacing_a_statement_keeps_every_other_line() -> None:
    session = _session()
    session.editor.goto(7)
    session.editor.replace("WAIT 0.2s")
    assert session.editor.text == ODD.replace("  WAIT 0.1s\n", "  WAIT 0.2s\n")


def test_inserting_and_deleting_keep_every_other_line() -> None:
    session = _session()
    session.editor.goto(6)
    session.editor.insert("PRINT n")
    assert session.editor.text == ODD.replace("  n=n+1\n", "  n=n+1\n  PRINT n\n")
    session.editor.goto(10)
    session.editor.delete()
    assert session.editor.text == ODD.replace("  n=n+1\n", "  n=n+1\n  PRINT n\n").replace('PRINT   "done"\n', "")
    session.editor.undo()
    session.editor.undo()
    assert session.editor.text == ODD
