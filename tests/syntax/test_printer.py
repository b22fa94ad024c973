"""Printing: source -> canonical text; canonical text comes back byte for byte; fmt is idempotent."""

from __future__ import annotations

import pytest

from orc_rpl.syntax.parser import parse
from orc_rpl.syntax.printer import print_program

CASES = [
    ("spaces around operators", "x=2*y+1\n", "x = 2 * y + 1\n"),
    ("redundant parentheses dropped", "x = (a * b) + c\n", "x = a * b + c\n"),
    ("needed parentheses kept", "x = (a + b) * c - (d - e)\n", "x = (a + b) * c - (d - e)\n"),
    ("double minus is not a comment", "x = - - y\n", "x = -(-y)\n"),
    ("attribute spacing", "MOVE g TO p WITH SPEED=0.5*Vmax VIA a,b\n", "MOVE g TO p WITH SPEED = 0.5 * Vmax VIA a, b\n"),
    ("continuation lines kept, indented two", "MOVE g TO p\n      WITH V=1mps\n", "MOVE g TO p\n  WITH V = 1mps\n"),
    ("blocks indented four", "IF a THEN\n  STOP\nENDIF\n", "IF a THEN\n    STOP\nENDIF\n"),
    ("trailing comment two spaces", "STOP      -- end\n", "STOP  -- end\n"),
    ("comment text kept verbatim", "--- header ---\n", "--- header ---\n"),
    ("case layout", "CASE i OF\n1 : STOP\n2, 3 :\nSTOP\nENDCASE\n", "CASE i OF\n    1 : STOP\n    2, 3 :\n        STOP\nENDCASE\n"),
    ("positional equality keeps its parentheses", "f((a = b))\n", "f((a = b))\n"),
    ("string escapes", 'PRINT "say \\"hi\\""\n', 'PRINT "say \\"hi\\""\n'),
    ("number text kept", "x = 1.50 + 1.5e-3 + 100mm/s\n", "x = 1.50 + 1.5e-3 + 100mm/s\n"),
    ("no final newline added back", "STOP", "STOP\n"),
    ("CRLF line endings", "FRAME f\r\n    STOP  -- x\r\nENDFRAME\r\n", "FRAME f\n    STOP  -- x\nENDFRAME\n"),
    ("tabs become spaces", "IF a THEN\n\tSTOP\nENDIF\n", "IF a THEN\n    STOP\nENDIF\n"),
]


@pytest.mark.parametrize("source, canonical", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_canonical_text(source: str, canonical: str) -> None:
    assert print_program(parse(source)) == canonical
    assert print_program(parse(canonical)) == canonical, "fmt must be idempotent"
