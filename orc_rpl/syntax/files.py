"""Program files: read a file and parse it with the syntax its suffix names; `load_program` gives the on-line tree of either."""

from __future__ import annotations

import re
from pathlib import Path

from orc_rpl.errors import Diagnostic, Location, SourceError, UsageError
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.offline_printer import print_offline
from orc_rpl.syntax.parser import parse
from orc_rpl.syntax.printer import print_program
from orc_rpl.syntax.reading import read_text

ONLINE_SUFFIXES = (".rpl",)
OFFLINE_SUFFIXES = (".orl",)
WORLD_SUFFIXES = (".yaml", ".yml")

#: `# world: ../../worlds/cell_thesis.yaml` among an off-line program's first comment lines names its world model.
_WORLD_LINE = re.compile(r"#\s*world:\s*(\S+)\s*$")


def read_source(path: str | Path) -> str:
    """The text of a program file; a clear UsageError naming the file when it cannot be read."""
    return read_text(path)


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


def interrupted_mark(path: str | Path) -> Path:
    """The file a command writing `path` with other outputs keeps beside it until every output is in place."""
    program = Path(path)
    return program.with_name(f".{program.name}.converting")


def parse_file(path: str | Path) -> tuple[str, n.Program]:
    """Read and parse a program file as written (`.rpl` on-line, `.orl` off-line); SourceError for syntax errors.

    A UsageError when a conversion that wrote this program and its world was interrupted between the two.
    """
    suffix = Path(path).suffix
    if suffix not in ONLINE_SUFFIXES + OFFLINE_SUFFIXES:
        raise UsageError(f"'{path}': unknown program suffix '{suffix}' (expected .rpl or .orl)")
    mark = interrupted_mark(path)
    if mark.exists():
        raise UsageError(f"'{path}' may be out of step with the files written with it: the conversion that wrote them "
                         f"was interrupted ('{mark}' lists them); convert again, or delete '{mark.name}' if they are right")
    text = read_source(path)
    return text, parse_text(text, path)


def declared_world(path: str | Path, text: str) -> Path | None:
    """The world named by a `# world: FILE` line among the program's leading comments (relative to the program);
    an on-line program's is a `-- world: FILE` line, naming the cell it runs in.

    SourceError at the line when it names anything but a `.yaml`/`.yml` file.
    """
    marker = "--" if Path(path).suffix in ONLINE_SUFFIXES else "#"
    for number, line in enumerate(text.splitlines(), start=1):
        if not line.startswith(marker):
            break
        shift = len(marker) - 1  # `--` is one character longer than `#`
        match = _WORLD_LINE.match("#" + line[len(marker):])
        if match:
            world = Path(path).parent / match.group(1)
            if world.suffix not in WORLD_SUFFIXES:  # never follow the line to a file that is not a world model
                location = Location(str(path), number, match.start(1) + 1 + shift, number, match.end(1) + 1 + shift)
                raise SourceError([Diagnostic(location, f"the world model '{match.group(1)}' must be a YAML file "
                                              f"({' or '.join(WORLD_SUFFIXES)})")], text)
            return world
    return None


def canonical_text(program: n.Program, path: str | Path) -> str:
    """The canonical text of a parsed program in the syntax its file's suffix names: what `orc fmt` writes."""
    return print_offline(program) if is_offline(path) else print_program(program)
