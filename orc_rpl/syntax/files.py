"""Program files: read a file and parse it with the syntax its suffix names; `load_program` gives the on-line tree of either."""

from __future__ import annotations

import re
from pathlib import Path

from orc_rpl.errors import UsageError
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.offline_printer import print_offline
from orc_rpl.syntax.parser import parse
from orc_rpl.syntax.printer import print_program

ONLINE_SUFFIXES = (".rpl",)
OFFLINE_SUFFIXES = (".orl",)

#: `# world: ../../worlds/cell_thesis.yaml` among an off-line program's first comment lines names its world model.
_WORLD_LINE = re.compile(r"#\s*world:\s*(\S+)\s*$")


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


def is_offline(path: str | Path) -> bool:
    """True for off-line programs (`.orl`)."""
    return Path(path).suffix in OFFLINE_SUFFIXES


def parse_text(text: str, path: str | Path) -> n.Program:
    """Parse text with the syntax the file's suffix names."""
    suffix = Path(path).suffix
    if suffix in OFFLINE_SUFFIXES:
        from orc_rpl.syntax.offline_parser import parse_offline

        return parse_offline(text, str(path))
    if suffix not in ONLINE_SUFFIXES:
        raise UsageError(f"'{path}': unknown program suffix '{suffix}' (expected .rpl or .orl)")
    return parse(text, str(path))


def parse_file(path: str | Path) -> tuple[str, n.Program]:
    """Read and parse a program file as written (`.rpl` on-line, `.orl` off-line); SourceError for syntax errors."""
    suffix = Path(path).suffix
    if suffix not in ONLINE_SUFFIXES + OFFLINE_SUFFIXES:
        raise UsageError(f"'{path}': unknown program suffix '{suffix}' (expected .rpl or .orl)")
    text = read_source(path)
    return text, parse_text(text, path)


def declared_world(path: str | Path, text: str) -> Path | None:
    """The world named by a `# world: FILE` line among the program's leading comments (relative to the program)."""
    for line in text.splitlines():
        if not line.startswith("#"):
            break
        match = _WORLD_LINE.match(line)
        if match:
            return Path(path).parent / match.group(1)
    return None


def canonical_text(program: n.Program, path: str | Path) -> str:
    """The canonical text of a parsed program in the syntax its file's suffix names: what `orc fmt` writes."""
    return print_offline(program) if is_offline(path) else print_program(program)
