"""Finds the grammar files, in a source checkout (`grammar/`) or inside an installed wheel."""

from __future__ import annotations

import os
import sys
from pathlib import Path

_PACKAGE_DIR = Path(__file__).resolve().parent.parent


def grammar_path(name: str) -> Path:
    """Path of a grammar file such as `rpl.lark`: the wheel's copy, else the checkout's `grammar/`."""
    for candidate in (_PACKAGE_DIR / "grammar" / name, _PACKAGE_DIR.parent / "grammar" / name):
        if candidate.is_file():
            return candidate
    raise FileNotFoundError(f"grammar file {name!r} is missing from the orc_rpl installation (looked in {_PACKAGE_DIR})")


def parser_cache(name: str) -> str | bool:
    """Where Lark keeps the analysed LALR parser of grammar `name` between runs, False when no folder can hold it.

    The folder is the user's cache (`$XDG_CACHE_HOME/orc_rpl`, else `~/.cache/orc_rpl`): the grammar's analysis
    takes longer than parsing a long program, and every `orc` command would pay it again. Lark stores the grammar's
    hash in the file and analyses the grammar again (and rewrites the file) when the hash differs or the file
    cannot be read, so a stale, foreign or half-written file costs one analysis, never a wrong parser.
    """
    root = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    folder = Path(root) / "orc_rpl"
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:
        return False
    return str(folder / f"{name}-py{sys.version_info[0]}{sys.version_info[1]}.lalr")
