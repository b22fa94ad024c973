"""Finds the grammar files, in a source checkout (`grammar/`) or inside an installed wheel."""

from __future__ import annotations

from pathlib import Path

_PACKAGE_DIR = Path(__file__).resolve().parent.parent


def grammar_path(name: str) -> Path:
    """Path of a grammar file such as `rpl.lark`: the wheel's copy, else the checkout's `grammar/`."""
    for candidate in (_PACKAGE_DIR / "grammar" / name, _PACKAGE_DIR.parent / "grammar" / name):
        if candidate.is_file():
            return candidate
    raise FileNotFoundError(f"grammar file {name!r} is missing from the orc_rpl installation (looked in {_PACKAGE_DIR})")
