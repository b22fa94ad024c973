"""Reading a user's text file safely: regular files only, bounded size, UTF-8 text, never binary; errors name the file.

A FIFO, `/dev/zero` or `/dev/urandom` given as a program, a world or a sidecar would block or never end
a plain `read()`; a binary file would reach the parsers as garbage. Type and size are checked before
the first byte is read.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from orc_rpl.errors import UsageError

#: Largest program, world or sidecar file read (bytes); real ones are a few kilobytes.
MAX_TEXT_BYTES = 16 * 1024 * 1024


def _kind(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISFIFO(mode):
        return "a pipe (FIFO)"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def read_text(path: str | Path, what: str = "") -> str:
    """The UTF-8 text of a regular file; UsageError naming the file (and `what` it is) otherwise."""
    name = f"{what} '{path}'" if what else f"'{path}'"
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise UsageError(f"cannot read {name}: no such file") from None
    except OSError as error:
        raise UsageError(f"cannot read {name}: {error.strerror}") from None
    if not stat.S_ISREG(info.st_mode):
        raise UsageError(f"cannot read {name}: it is {_kind(info.st_mode)}") from None
    if info.st_size > MAX_TEXT_BYTES:
        raise UsageError(f"cannot read {name}: {info.st_size} bytes is too large (at most {MAX_TEXT_BYTES})")
    try:
        with open(path, "rb") as handle:
            data = handle.read(MAX_TEXT_BYTES + 1)
    except OSError as error:
        raise UsageError(f"cannot read {name}: {error.strerror}") from None
    if len(data) > MAX_TEXT_BYTES:
        raise UsageError(f"cannot read {name}: too large (at most {MAX_TEXT_BYTES} bytes)")
    nul = data.find(b"\x00")
    if nul >= 0:
        raise UsageError(f"cannot read {name}: a binary file, not text (a NUL byte at {_where(data, nul)})")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as error:
        raise UsageError(f"cannot read {name}: not UTF-8 text (at {_where(data, error.start)})") from None


def _where(data: bytes, offset: int) -> str:
    """`line L, column C` (1-based, columns in bytes) of a byte offset."""
    line = data.count(b"\n", 0, offset) + 1
    column = offset - (data.rfind(b"\n", 0, offset) + 1) + 1
    return f"line {line}, column {column}"
