"""Programs written in the style of docs/language.md by someone else: valid ones check clean, broken ones fail at the right line."""

from __future__ import annotations

from pathlib import Path

import pytest

from orc_rpl.checking.checker import check_program
from orc_rpl.errors import SourceError
from orc_rpl.syntax.parser import parse

FOREIGN = Path(__file__).parent / "foreign"


def diagnostics(text: str) -> list[tuple[int, int]]:
    try:
        program = parse(text, "foreign.rpl")
    except SourceError as error:
        return [(d.location.line, d.location.column) for d in error.diagnostics]
    return [(d.location.line, d.location.column) for d in check_program(program, "foreign.rpl")]


def test_language_md_examples_check_clean() -> None:
    text = (FOREIGN / "language_md_examples.rpl").read_text()
    assert diagnostics(text) == []


BROKEN = [
    ("typo in a motion keyword on line 4", "TOOL t = POSE(0, 0, 0, 0, 0, 0)\nPOS p = POSE(1m, 0, 1m, 0, 0, 0)\n\nLMOV t TO p\n",
     [(4, 1)]),
    ("thesis layout with an unknown attribute", "TOOL g = TRANSL(0, 0, 0)\nPOS e = TRANSL(1m, 0, 1m)\nMOVE g TO e\n  WITH SPEED=0.15*mps\n  WITH FROCE=1N\n",
     [(5, 8)]),
    ("missing ENDFRAME", "FRAME f = TRANSL(1m, 0, 0)\nFRAME f\n    STOP\n", [(2, 1)]),
    ("position used outside its frame", "FRAME f = TRANSL(1m, 0, 0)\nPOS p = TRANSL(0, 0, 0) IN f\nMOVE ARM TO p\n", [(3, 13)]),
    ("speed given as a force", "POS p = TRANSL(1m, 0, 1m)\nMOVE ARM TO p WITH SPEED = 40N\n", [(2, 28)]),
]


@pytest.mark.parametrize("text, expected", [c[1:] for c in BROKEN], ids=[c[0] for c in BROKEN])
def test_broken_program_is_rejected_at_the_right_place(text: str, expected: list[tuple[int, int]]) -> None:
    assert diagnostics(text) == expected
