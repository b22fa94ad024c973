"""Program files: read a file and parse it with the syntax its suffix names."""

from __future__ import annotations

from pathlib import Path

from orc_rpl.errors import UsageError
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.parser import parse

ONLINE_SUFFIXES = (".rpl",)


def read_source(path: str | Path) -> str:
    """The text of a program file; a clear UsageError naming the file when it cannot be read."""
    file = Path(path)
    try:
        data = file.read_bytes()
    except FileNotFoundError:
        raise UsageError(f"cannot read '{path}': no such file") from None
    except IsADirectoryError:
        raise UsageError(f"cannot read '{path}': it is a directory") from None
    except OSError as error:
        raise UsageError(f"cannot read '{path}': {error.strerror}") from None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as error:
        raise UsageError(f"cannot read '{path}': not UTF-8 text (byte {error.start})") from None


def parse_file(path: str | Path) -> tuple[str, n.Program]:
    """Read and parse a program file; raises SourceError for syntax errors, UsageError for unreadable files."""
    suffix = Path(path).suffix
    if suffix not in ONLINE_SUFFIXES:
        raise UsageError(f"'{path}': unknown program suffix '{suffix}' (expected .rpl)")
    text = read_source(path)
    return text, parse(text, str(path))
