"""Round trips over every program of the repository: canonical files come back byte for byte."""

from __future__ import annotations

from pathlib import Path

import pytest

from orc_rpl.syntax.parser import parse
from orc_rpl.syntax.printer import print_program
from tests.conftest import online_programs


@pytest.mark.parametrize("path", online_programs(), ids=lambda p: p.name)
def test_program_is_canonical_and_round_trips(path: Path) -> None:
    text = path.read_text(encoding="utf-8")
    tree = parse(text, str(path))
    printed = print_program(tree)
    assert printed == text, f"{path.name} is not canonical: run `orc fmt --write {path}`"
    assert parse(printed) == tree
