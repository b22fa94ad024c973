"""Static checks of an off-line program against its world: unknown world paths, then the on-line checker on its on-line form."""

from __future__ import annotations

from pathlib import Path

from orc_rpl.errors import Diagnostic, Location, SourceError, UsageError
from orc_rpl.syntax import nodes as n
from orc_rpl.transform.job import TransformError
from orc_rpl.transform.loading import moving_frames, world_attributes
from orc_rpl.transform.pipeline import to_online
from orc_rpl.transform.references import world_diagnostics
from orc_rpl.world import World, load_world


def load_world_file(path: str | Path) -> World:
    """A world model file; a missing or unreadable file is a SourceError at line 1 so every command reports it the same way."""
    if not Path(path).exists():
        raise SourceError([Diagnostic(Location(str(path), 1, 1), f"world model '{path}' does not exist")])
    try:
        return load_world(path)
    except UsageError as error:  # not a regular text file: said without its content
        raise SourceError([Diagnostic(Location(str(path), 1, 1), str(error))]) from None


def check_offline(program: n.Program, world: World, path: str, source: str, registry=None) -> list[Diagnostic]:  # type: ignore[no-untyped-def]
    """Unknown world paths at their line and column; if there are none, the on-line checks of the transformed program."""
    from orc_rpl.checking.checker import check_program

    found = world_diagnostics(program, world, path)
    if found:
        return found
    try:
        online = to_online(program, world, path, source).program
    except SourceError as error:
        return error.diagnostics
    except TransformError as error:
        return [Diagnostic(Location(path, 1, 1), str(error))]
    return check_program(online, path, registry, world_attributes(world), moving_frames(world))
