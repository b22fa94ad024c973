"""Loading a program to run it: on-line text as it is, an off-line program transformed with its world model."""

from __future__ import annotations

from pathlib import Path

from orc_rpl.errors import UsageError
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.files import declared_world, is_offline, parse_file
from orc_rpl.transform.pipeline import to_online
from orc_rpl.world import World, load_world

#: Object name -> its soft and spatial attributes (`pallet` -> {rows: 3, next_row: 1}), values as RPL values.
WorldAttributes = dict[str, dict[str, object]]


def world_attributes(world: World) -> WorldAttributes:
    """The soft and spatial attributes of every object that has any: what programs read as `pallet.next_row`."""
    return {obj.name: {**obj.spatial, **obj.soft} for obj in world.objects if obj.spatial or obj.soft}


def moving_frames(world: World) -> dict[str, str]:
    """The world's moving frames and how each moves (linear, rotary, conveyor): what programs may name as frames
    and, but for conveyors, give values to with AXES(p, ...)."""
    return {name: world.object(name).axis.joint for name in world.moving_frames()}  # type: ignore[union-attr]


def load_program_and_attributes(path: str | Path, world: str | Path | None = None) -> tuple[str, n.Program, WorldAttributes]:
    """`load_program`, and the soft and spatial attributes of the program's world (on-line: of `world` when given);
    an off-line program's world is read once for both."""
    text, program = parse_file(path)
    if is_offline(path):
        loaded = _offline_world(path, text, world)
        return text, to_online(program, loaded, str(path), text).program, world_attributes(loaded)
    if world is None or not Path(world).is_file():
        return text, program, {}
    return text, program, world_attributes(load_world(Path(world)))


def load_program(path: str | Path, world: str | Path | None = None) -> tuple[str, n.Program]:
    """The source text and the on-line tree of a program: an `.orl` file is transformed with its world model first.

    The world is `world`, else the program's `# world: FILE` line. Spans of the tree point into the source text.
    """
    text, program = parse_file(path)
    if not is_offline(path):
        return text, program
    return text, to_online(program, _offline_world(path, text, world), str(path), text).program


def _offline_world(path: str | Path, text: str, world: str | Path | None) -> World:
    """The world model of an off-line program: `world`, else its `# world: FILE` line (UsageError without one)."""
    world_path = Path(world) if world is not None else declared_world(path, text)
    if world_path is None:
        raise UsageError(f"'{path}' is an off-line program: give its world model (--world FILE or a '# world: FILE' line)")
    if not world_path.is_file():
        raise UsageError(f"world model '{world_path}' of '{path}' does not exist")
    return load_world(world_path)
