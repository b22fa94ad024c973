"""Shared test fixtures: paths of the repository's programs and worlds."""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PROGRAMS = ROOT / "programs"


def online_programs() -> list[Path]:
    """Every on-line program in the repository."""
    return sorted(PROGRAMS.glob("online/*.rpl"))


@pytest.fixture
def root() -> Path:
    return ROOT
