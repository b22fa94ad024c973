"""The world model's values: objects with their model, spatial and soft attributes (thesis 7.1), all immutable."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Mapping

from orc_rpl.errors import Location, OrcError
from orc_rpl.world.axes import AxisSpec
from orc_rpl.world.pose import WORLD, Pose
from orc_rpl.world.values import SoftValue

#: The robot's base and its flange; the flange's pose relative to the base is known only at run time.
ROBOT = "robot"
FLANGE = "flange"
#: Names every world has; no object may take them.
PREDEFINED = (WORLD, ROBOT, FLANGE)

NAME_RE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
#: `object`, `object.frame`, `object.path`, `object.path[3]` (indices start at 1, as in the language).
DOTTED_RE = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)(?:\.([A-Za-z_][A-Za-z0-9_]*)(?:\[(\d+)\])?)?")

NOWHERE = Location("<world>", 1, 1)


class WorldError(OrcError):
    """A query or edit the world cannot answer (unknown name, cycle an edit would make, flange pose unknown)."""


@dataclass(frozen=True, slots=True)
class ModelAttributes:
    """How an object looks (thesis: model attributes), used only by graphics and the simulated cell."""

    geometry: str | None = None                   #: box | cylinder | sphere | mesh
    size_m: tuple[float, ...] = ()                #: box (x, y, z); cylinder (radius, height); sphere (radius,)
    colour: str | tuple[float, ...] | None = None  #: a name or [r, g, b(, a)] in 0..1
    mesh: str | None = None                       #: mesh file, relative to the world file
    offset: Pose | None = None                    #: the geometry's centre relative to the object (None: at its origin)


@dataclass(frozen=True, slots=True)
class Position:
    """A named frame of an object (a spatial attribute), relative to that object."""

    name: str
    pose: Pose                                       #: frame = the owning object
    location: Location = field(default=NOWHERE, compare=False, repr=False)


@dataclass(frozen=True, slots=True)
class PathAttribute:
    """An ordered list of positions on an object (a seam, an edge, a row of spots)."""

    name: str
    points: tuple[Pose, ...]                         #: each relative to the owning object
    refs: tuple[str | None, ...]                     #: the frame an element names, None for a written pose
    location: Location = field(default=NOWHERE, compare=False, repr=False)


@dataclass(frozen=True, slots=True)
class WorldObject:
    """A node of the world tree: a pose relative to its parent and its attributes."""

    name: str
    parent: str                                      #: an object, `robot`, `flange` or `world`
    pose: Pose                                       #: relative to the parent (frame = parent)
    online_frame: bool = False                       #: tagged: positions below are taught relative to it
    tool: bool = False                               #: a tool centre point a motion can move (mounted on the flange)
    model: ModelAttributes | None = None             #: off-line only
    model_key: str | None = None                     #: on-line: the key of the model attributes kept off-line
    frames: tuple[Position, ...] = ()
    paths: tuple[PathAttribute, ...] = ()
    soft_items: tuple[tuple[str, SoftValue], ...] = ()
    spatial_items: tuple[tuple[str, SoftValue], ...] = ()   #: named spatial numbers (a pallet's rows, a pitch)
    location: Location = field(default=NOWHERE, compare=False, repr=False)
    work: bool = False                               #: the robot's work (a casting to grind): contact is no collision
    axis: AxisSpec | None = None                     #: a moving frame: an external axis or a conveyor moves it

    @property
    def soft(self) -> Mapping[str, SoftValue]:
        """Soft attributes (program state kept with the object), read-only."""
        return MappingProxyType(dict(self.soft_items))

    @property
    def spatial(self) -> Mapping[str, SoftValue]:
        """Named spatial numbers (counts, pitches) that positions are computed from, read-only."""
        return MappingProxyType(dict(self.spatial_items))

    def frame(self, name: str) -> Position | None:
        """A named frame of this object, or None."""
        return next((f for f in self.frames if f.name == name), None)

    def path(self, name: str) -> PathAttribute | None:
        """A named path of this object, or None."""
        return next((p for p in self.paths if p.name == name), None)


@dataclass(frozen=True, slots=True)
class RobotEntry:
    """The robot of the cell: which model (`worlds/<model>.xml`) and where its base stands."""

    model: str
    pose: Pose                                       #: base relative to its parent
    location: Location = field(default=NOWHERE, compare=False, repr=False)
    parent: str = WORLD                              #: `world`, or the moving frame the base rides on (a track)


@dataclass(frozen=True, slots=True)
class OnlineFrame:
    """A tagged on-line frame with the on-line frame it is nested in and its pose relative to that."""

    name: str
    parent: str                                      #: the enclosing on-line frame, or `world`
    pose: Pose                                       #: relative to `parent`
