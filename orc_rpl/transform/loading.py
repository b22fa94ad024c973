"""Loading a program to run it: on-line text as it is, an off-line program transformed with its world model."""

from __future__ import annotations

from pathlib import Path

from orc_rpl.errors import UsageError
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.files import declared_world, is_offline, parse_file
from orc_rpl.transform.pipeline import to_online
from orc_rpl.world import load_world


def load_program(path: str | Path, world: str | Path | None = None) -> tuple[str, n.Program]:
    """The source text and the on-line tree of a program: an `.orl` file is transformed with its world model first.

    The world is `world`, else the program's `# world: FILE` line. Spans of the tree point into the source text.
    """
    text, program = parse_file(path)
    if not is_offline(path):
        return text, program
    world_path = Path(world) if world is not None else declared_world(path, text)
    if world_path is None:
        raise UsageError(f"'{path}' is an off-line program: give its world model (--world FILE or a '# world: FILE' line)")
    if not world_path.is_file():
        raise UsageError(f"world model '{world_path}' of '{path}' does not exist")
    return text, to_online(program, load_world(world_path), str(path), text).program
