"""One document as the editor holds it: parsed, checked (an off-line program against its world), with the world it names."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from orc_rpl.application.registry import Registry
from orc_rpl.checking.checker import check_program
from orc_rpl.errors import Diagnostic, Location, OrcError, SourceError
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.files import ONLINE_SUFFIXES, declared_world, is_offline, parse_text
from orc_rpl.transform.checks import check_offline, load_world_file
from orc_rpl.transform.loading import moving_frames
from orc_rpl.world import World


@dataclass(frozen=True)
class Analysis:
    """What the server knows about one open document after its last change."""

    path: str                                    #: the file's path (or the URI's path for an unsaved buffer)
    text: str
    program: n.Program | None                    #: None while the text does not parse
    diagnostics: list[Diagnostic] = field(default_factory=list)
    world: World | None = None                   #: the world of an off-line program, when found
    world_line: int = 0                          #: the `# world:` line (1-based), 0 when there is none
    salvaged: n.Program | None = None            #: while the text does not parse: the program without its bad lines

    @property
    def offline(self) -> bool:
        return is_offline(self.path)


def world_line(text: str, path: str = "") -> int:
    """The 1-based line of the `# world: FILE` comment among the leading comments (an on-line program's
    `-- world: FILE`, naming its cell), 0 when there is none."""
    marker = "--" if Path(path).suffix in ONLINE_SUFFIXES else "#"
    for number, line in enumerate(text.splitlines(), start=1):
        if not line.startswith(marker):
            break
        if declared_world(path, line) is not None:  # the regular expression of the one `# world:` reader
            return number
    return 0


def _at_world_line(diagnostics: list[Diagnostic], path: str, text: str, line: int, world_path: Path) -> list[Diagnostic]:
    """Errors inside the world file, shown on the program's `# world:` line (the editor has the program open)."""
    lines = text.splitlines()
    end_column = len(lines[line - 1]) + 1 if 0 < line <= len(lines) else 0
    out = []
    for d in diagnostics:
        if d.location.path == path:
            out.append(d)
            continue
        where = f"{world_path}:{d.location.line}:{d.location.column}: " if world_path.is_file() else ""
        out.append(Diagnostic(Location(path, line or 1, 1, line or 1, end_column), where + d.message, d.hint))
    return out


def salvage(text: str, path: str, diagnostics: list[Diagnostic]) -> n.Program | None:
    """The program with the lines of its syntax errors blanked, so completion still knows the names declared elsewhere."""
    lines = text.split("\n")
    for _ in range(3):  # blanking a line may uncover an error further down; give up after a few
        for d in diagnostics:
            if 0 < d.location.line <= len(lines):
                lines[d.location.line - 1] = ""
        try:
            return parse_text("\n".join(lines), path)
        except SourceError as error:
            diagnostics = error.diagnostics
        except OrcError:
            return None
    return None


def _world(text: str, path: str) -> tuple[World | None, list[Diagnostic], int]:
    """The world named by an off-line program's `# world:` line, the errors loading it, and that line."""
    line = world_line(text, path)
    world_path = declared_world(path, text)
    if world_path is None:
        return None, [], 0
    try:
        return load_world_file(world_path), [], line
    except SourceError as error:
        return None, _at_world_line(error.diagnostics, path, text, line, world_path), line


def analyse(text: str, path: str, registry: Registry) -> Analysis:
    """Parse and check one document's text; every error becomes a diagnostic, never an exception."""
    world, world_errors, line = _world(text, path)
    try:
        program = parse_text(text, path)
    except SourceError as error:
        return Analysis(path, text, None, list(error.diagnostics), world, line, salvage(text, path, error.diagnostics))
    except OrcError as error:  # an unknown suffix: say so at the top of the file
        return Analysis(path, text, None, [Diagnostic(Location(path, 1, 1), str(error))])
    if not is_offline(path):  # its `-- world:` cell: the moving frames it may name
        frames = None if world is None else moving_frames(world)
        return Analysis(path, text, program, world_errors + check_program(program, path, registry, None, frames))
    if world is None:  # without a world model only the syntax can be checked
        return Analysis(path, text, program, world_errors, None, line)
    diagnostics = check_offline(program, world, path, text, registry)
    return Analysis(path, text, program, _at_world_line(diagnostics, path, text, line, Path(world.path)), world, line)
