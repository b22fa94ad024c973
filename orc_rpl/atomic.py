"""Atomic file output: a temporary file in the same folder, flushed, then renamed over the target."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path


def _new_file_mode() -> int:
    """The mode a new file gets from the user's umask (mkstemp alone would give 0600)."""
    umask = os.umask(0o022)
    os.umask(umask)
    return 0o666 & ~umask


def prepare_atomic(path: str | Path, text: str) -> str:
    """Write `text` to a temporary beside `path`'s target (a symlink is followed) and return the temporary's path.

    The temporary has the target's mode, or the user's umask for a new file; the caller renames it
    over `os.path.realpath(path)` or removes it.
    """
    target = Path(os.path.realpath(path))
    mode = target.stat().st_mode & 0o777 if target.exists() else _new_file_mode()
    fd, temporary = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as handle:
            handle.write(text)
            handle.flush()
            os.fsync(handle.fileno())
        os.chmod(temporary, mode)
    except BaseException:
        discard(temporary)
        raise
    return temporary


def discard(temporary: str) -> None:
    """Remove a temporary that will not be renamed (already gone is fine)."""
    try:
        os.unlink(temporary)
    except FileNotFoundError:
        pass


def write_text_atomic(path: str | Path, text: str) -> None:
    """Replace `path` with `text` so that a crash leaves either the old file or the new one, never half of one.

    A symlink stays a symlink: its target is replaced (`fmt --write` on a link edits the file it points to).
    """
    temporary = prepare_atomic(path, text)
    try:
        os.replace(temporary, os.path.realpath(path))
    except BaseException:
        discard(temporary)
        raise
