"""The off-line syntax: each construct parses to the same tree as its on-line spelling; errors at file:line:col."""

from __future__ import annotations

import pytest

from orc_rpl.errors import SourceError
from orc_rpl.syntax.offline_parser import parse_offline
from orc_rpl.syntax.offline_printer import print_offline
from orc_rpl.syntax.parser import parse

#: (off-line, on-line) pairs of canonical text: both parse to one tree, each prints back to itself.
SAME_TREE = [
    ("moveto", "moveto pos0\n", "MOVE ARM TO pos0\n"),
    ("world-path", "moveto base_plate.pos1\n", "MOVE ARM TO base_plate.pos1\n"),
    ("clauses", "moveto p speed=0.5 * Vmax via a, b until DigIn[1] == 1\n",
     "MOVE ARM TO p WITH SPEED = 0.5 * Vmax VIA a, b UNTIL DigIn[1] = 1\n"),
    ("tool", "grindmove grinder along casting.right_edge force=grind_force grinding=grind_pars\n",
     "GRINDMOVE grinder ALONG casting.right_edge WITH FORCE = grind_force WITH GRINDING = grind_pars\n"),
    ("move-arm-via-first", "move ARM via a to b\n", "MOVE ARM VIA a TO b\n"),
    ("continuation", "move grinder to right_edge  # start\n    with speed=0.15 * mps\n    with force=MyForce1\n",
     "MOVE grinder TO right_edge  -- start\n  WITH SPEED = 0.15 * mps\n  WITH FORCE = MyForce1\n"),
    ("output-binding", "identmove gripper to DropPositions[Id] via TopPos Id=IDENT(proc, parts)\n",
     "IDENTMOVE gripper TO DropPositions[Id] VIA TopPos WITH Id = IDENT(proc, parts)\n"),
    ("declarations", "pos p = POSE(1mm, 0, 0, 0, 180deg, 0) in base_plate\nconst Vmax = 1.5mps\nenum Part = NoObject, Bolt\n",
     "POS p = POSE(1mm, 0, 0, 0, 180deg, 0) IN base_plate\nCONST Vmax = 1.5mps\nENUM Part = NoObject, Bolt\n"),
    ("install", "install Gun as SpotGun close=DigOut[3] reaction=80ms\n",
     "INSTALL Gun AS SpotGun WITH CLOSE = DigOut[3] WITH REACTION = 80ms\n"),
    ("if", "if n > 3 and not done:\n    moveto home\nelif n == 3:\n    wait 1s\nelse:\n    stop\n",
     "IF n > 3 AND NOT done THEN\n    MOVE ARM TO home\nELSIF n = 3 THEN\n    WAIT 1s\nELSE\n    STOP\nENDIF\n"),
    ("for", "for i in 1..10 step 2:\n    weldmove weldgun to door.spots[i]\n",
     "FOR i FROM 1 TO 10 STEP 2 DO\n    WELDMOVE weldgun TO door.spots[i]\nENDFOR\n"),
    ("while", "while DigIn[1] != 0:  # wait for the part\n    wait 10ms\n",
     "WHILE DigIn[1] <> 0 DO  -- wait for the part\n    WAIT 10ms\nENDWHILE\n"),
    ("case", 'case Id:\n    NoObject: print("nothing grasped")\n    Bolt, Nut:\n        Gripper.Open\n    else: raise UnknownPart\n',
     'CASE Id OF\n    NoObject : PRINT "nothing grasped"\n    Bolt, Nut :\n        Gripper.Open\n    ELSE : RAISE UnknownPart\nENDCASE\n'),
    ("frame-block", "frame base_plate:\n    moveto pos1\n", "FRAME base_plate\n    MOVE ARM TO pos1\nENDFRAME\n"),
    ("try", "try:\n    trackmove effector to EndPos\nexcept SeamLost:\n    moveto safe_pos\n",
     "TRY\n    TRACKMOVE effector TO EndPos\nON SeamLost :\n    MOVE ARM TO safe_pos\nENDTRY\n"),
    ("routines", "def GrinderOff:\n    DigOut[5] = 0\ndef Pick(p):\n    moveto p\nfunc ramp(s):\n    return 20N + 10N * s\n",
     "PROC GrinderOff\n    DigOut[5] = 0\nENDPROC\nPROC Pick(p)\n    MOVE ARM TO p\nENDPROC\nFUNC ramp(s)\n    RETURN 20N + 10N * s\nENDFUNC\n"),
    ("end-comment", "while x:\n    wait 1s\nend  # loop done\n", "WHILE x DO\n    WAIT 1s\nENDWHILE  -- loop done\n"),
    ("empty-block", "if x:\nelse:\n    stop\n", "IF x THEN\nELSE\n    STOP\nENDIF\n"),
    ("trailing-blank-in-block", "if x:\n    stop\n    \nwait 1s\n", "IF x THEN\n    STOP\n\nENDIF\nWAIT 1s\n"),
    ("blank-after-block", "if x:\n    stop\n\nwait 1s\n", "IF x THEN\n    STOP\nENDIF\n\nWAIT 1s\n"),
    ("comments", "# head\n\nwait 1s  # short\n", "-- head\n\nWAIT 1s  -- short\n"),
    ("print-wait-until", "print()\nprint(a, \"b\")\nwait until DigIn[2] == 1 timeout 3s\n",
     "PRINT\nPRINT a, \"b\"\nWAIT UNTIL DigIn[2] = 1 TIMEOUT 3s\n"),
    ("true-false", "ok = true or false\n", "ok = TRUE OR FALSE\n"),
    ("keyword-arguments", "pars = GrindingPars(tolerance=0.2mm, max_passes=4)\n",
     "pars = GrindingPars(tolerance = 0.2mm, max_passes = 4)\n"),
]


@pytest.mark.parametrize("offline, online", [(o, n) for _, o, n in SAME_TREE], ids=[c[0] for c in SAME_TREE])
def test_offline_and_online_spellings_parse_to_one_tree(offline: str, online: str) -> None:
    tree = parse_offline(offline, "t.orl")
    assert tree == parse(online, "t.rpl")
    assert print_offline(tree) == offline


def test_a_field_may_be_named_like_an_offline_keyword() -> None:
    assert parse_offline("moveto casting.path\n") == parse("MOVE ARM TO casting.path\n")


ERRORS = [
    ("keyword-as-name", "to = 3\n", "t.orl:1:1: 'to' is an off-line keyword and cannot be used as a name"),
    ("offline-keyword-in-expression", "x = step + 1\n", "t.orl:1:5: 'step' is an off-line keyword and cannot be used as a name"),
    ("online-reserved-word", "MOVE = 3\n", "t.orl:1:1: 'MOVE' is a reserved word and cannot be used as a name"),
    ("unexpected-indent", "wait 1s\n    wait 2s\n", "t.orl:2:1: unexpected indentation"),
    ("bad-dedent", "if x:\n        wait 1s\n    wait 2s\n", "t.orl:3:5: this line's indentation matches no enclosing block"),
    ("else-alone", "else:\n    stop\n", "t.orl:1:1: 'else' must follow the block of an if or a case at its indentation"),
    ("continuation-of-nothing", "x = 1\n    with speed=1\n", "t.orl:2:5: a line starting with with continues only a motion or an install statement"),
    ("unclosed-string", 'print("abc)\n', "t.orl:1:7: string is not closed before the end of the line"),
    ("missing-colon", "if x\n    stop\n", "t.orl:2:1: unexpected indentation\n    2 |     stop\n      | ^\n      = hint: is a ':' missing at the end of line 1?"),
]


@pytest.mark.parametrize("text, expected", [(t, e) for _, t, e in ERRORS], ids=[c[0] for c in ERRORS])
def test_offline_errors_point_at_file_line_and_column(text: str, expected: str) -> None:
    with pytest.raises(SourceError) as caught:
        parse_offline(text, "t.orl")
    assert caught.value.format().startswith(expected), caught.value.format()


def test_several_errors_are_reported_in_one_pass() -> None:
    with pytest.raises(SourceError) as caught:
        parse_offline("moveto\nwait 1s\nx = = 2\nmoveto p\n", "t.orl")
    assert [d.location.line for d in caught.value.diagnostics] == [1, 3]


def test_error_shows_the_line_and_a_caret() -> None:
    with pytest.raises(SourceError) as caught:
        parse_offline("moveto p\nmoveto q speed=\n", "prog.orl")
    assert caught.value.format().splitlines()[1:3] == ["    2 | moveto q speed=", "      |                ^"]
