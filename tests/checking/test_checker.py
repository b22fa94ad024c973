"""The checker: golden messages for each static rule, at the right line and column, all errors in one run."""

from __future__ import annotations

import pytest

from orc_rpl.checking.checker import check_program
from orc_rpl.syntax.parser import parse

PRELUDE = """TOOL grinder = POSE(0, 0, 150mm, 0, 0, 0)
FRAME base_plate = POSE(900mm, 0, 500mm, 0, 0, 0)
POS p_world = POSE(900mm, 0, 600mm, 0, 180deg, 0)
POS p_plate = POSE(100mm, 0, 50mm, 0, 180deg, 0) IN base_plate
CONST Vmax = 1.5mps
"""
PRELUDE_LINES = PRELUDE.count("\n")


def messages(body: str) -> list[str]:
    """`line:col: message` of every diagnostic, lines counted from the first line after the prelude."""
    program = parse(PRELUDE + body, "p.rpl")
    return [f"{d.location.line - PRELUDE_LINES}:{d.location.column}: {d.message}" for d in check_program(program, "p.rpl")]


GOLDEN = [
    ("undefined name with did-you-mean", "MOVE grinder TO p_wrld\n",
     ["1:17: undefined name 'p_wrld'; did you mean 'p_world'?"]),
    ("unknown motion keyword", "GRNDMOVE grinder ALONG [p_world]\n",
     ["1:1: unknown motion keyword 'GRNDMOVE'; did you mean 'GRINDMOVE'?"]),
    ("unknown attribute", "GRINDMOVE grinder ALONG [p_world] WITH FORC = 30N\n",
     ["1:40: GRINDMOVE does not accept attribute 'FORC'; did you mean 'FORCE'?"]),
    ("attribute of the wrong dimension", "MOVE grinder TO p_world WITH SPEED = 40N\n",
     ["1:38: attribute SPEED of MOVE expects a velocity or a number, got a force"]),
    ("alias of an attribute", "MOVE grinder TO p_world WITH V = 0.5 * Vmax\n", []),
    ("wrong arity", "POS q = POSE(1mm, 2mm, 3mm)\n", ["1:9: POSE takes 6 arguments, got 3"]),
    ("dimension mismatch names both", "x = 1s + 2mm\n", ["1:5: cannot add time (s) and length (m)"]),
    ("duplicate declaration", "VAR n = 1\nCONST n = 2\n", ["2:7: 'n' is already declared at line 6"]),
    ("return with value outside a FUNC", "PROC Foo\n    RETURN 3\nENDPROC\n", ["2:5: RETURN with a value outside a FUNC"]),
    ("frame rule outside blocks", "MOVE grinder TO p_plate\n",
     ["1:17: target 'p_plate' is relative to base_plate, but this motion is outside every FRAME block (relative to world)"]),
    ("frame rule inside a block", "FRAME base_plate\n    MOVE grinder TO p_world\nENDFRAME\n",
     ["2:21: target 'p_world' is relative to world, but this motion is inside FRAME base_plate"]),
    ("frame rule follows OFFS", "FRAME base_plate\n    MOVE grinder TO OFFS(p_plate, 0, 0, 50mm)\nENDFRAME\n", []),
    ("HERE is relative to the block", "FRAME base_plate\n    MOVE grinder TO HERE\nENDFRAME\n", []),
    ("joints go anywhere", "POS home = JOINTS(0, 0, 0, 0, 90deg, 0)\nFRAME base_plate\n    MOVE ARM TO home\nENDFRAME\n", []),
    ("unknown frame block", "FRAME base_plat\nENDFRAME\n", ["1:7: unknown frame 'base_plat'; did you mean 'base_plate'?"]),
    ("unknown tool", "MOVE grindr TO p_world\n", ["1:6: unknown tool 'grindr'; did you mean 'grinder'?"]),
    ("motion without target", "MOVE grinder WITH SPEED = 1mps\n", ["1:1: MOVE needs TO a target or ALONG a path"]),
    ("CMOVE needs a via point", "CMOVE grinder TO p_world\n", ["1:1: CMOVE needs a VIA point (the circle passes through it)"]),
    ("WELDMOVE needs a SpotGun", "WELDMOVE grinder TO p_world\n",
     ["1:10: WELDMOVE needs a SpotGun installed on tool 'grinder'"]),
    ("SpotGun mounted on the tool", "INSTALL grinder AS SpotGun WITH REACTION = 80ms\nWELDMOVE grinder TO p_world\n", []),
    ("unknown INSTALL kind", "INSTALL Gun AS SpotGn\n", ["1:16: unknown INSTALL kind 'SpotGn'; did you mean 'SpotGun'?"]),
    ("unknown method of an installed object", "INSTALL g AS Gripper WITH CLOSE = DigOut[1]\ng.Clse\n",
     ["2:3: a Gripper has no method or value 'Clse'; did you mean 'Close'?"]),
    ("constant cannot be assigned", "Vmax = 2mps\n", ["1:1: 'Vmax' is a CONST and cannot be assigned"]),
    ("inputs cannot be assigned", "DigIn[1] = 1\n", ["1:1: DigIn is an input and cannot be assigned"]),
    ("WAIT needs a time", "WAIT 5mm\n", ["1:6: WAIT expects a time, got a length"]),
    ("pose fields", "x = p_world.q\n", ["1:13: a pose has no field 'q'; its fields are x, y, z, a, b, c"]),
    ("routines may be called before they are written", "Later\nPROC Later\nENDPROC\n", []),
    ("routine arity", "FUNC f(a, b)\n    RETURN a\nENDFUNC\nx = f(1)\n", ["4:5: FUNC f takes 2 arguments, got 1"]),
    ("FUNC as attribute value", "FUNC ramp(s)\n    RETURN 20N + 10N * s\nENDFUNC\nGRINDMOVE grinder TO p_world WITH FORCE = ramp\n", []),
    ("globals visible in routines; locals stay local", "VAR count = 0\nPROC Bump\n    count = count + 1\n    tmp = 1\nENDPROC\nx = tmp\n",
     ["6:5: undefined name 'tmp'"]),
    ("IDENT binds its output name", "ENUM Part = NoObject, Bolt\nFUNC proc(r)\n    RETURN Bolt\nENDFUNC\n"
     "IDENTMOVE grinder TO p_world VIA p_world WITH Id = IDENT(proc, [NoObject, Bolt])\nCASE Id OF\n    Bolt : STOP\nENDCASE\n", []),
]


@pytest.mark.parametrize("body, expected", [c[1:] for c in GOLDEN], ids=[c[0] for c in GOLDEN])
def test_check_rule(body: str, expected: list[str]) -> None:
    assert messages(body) == expected


def test_all_errors_of_a_file_are_reported_in_file_order() -> None:
    found = messages("MOVE grinder TO nowhere\nx = 1s + 1m\nWAIT 3N\n")
    assert [m.split(":")[0] for m in found] == ["1", "2", "3"]


def test_full_message_has_location_line_and_caret() -> None:
    program = parse("MOVE ARM TO p WITH SPEED = 40N\n", "prog.rpl")
    source = "MOVE ARM TO p WITH SPEED = 40N\n"
    text = [d.format(source) for d in check_program(program, "prog.rpl")]
    assert text[-1] == (
        "prog.rpl:1:28: attribute SPEED of MOVE expects a velocity or a number, got a force\n"
        "    1 | MOVE ARM TO p WITH SPEED = 40N\n"
        "      |                            ^^^"
    )
