"""What the passes hand on: the program, the world, the on-line names, the entities used and their on-line frames."""

from __future__ import annotations

from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Mapping

from orc_rpl.errors import Diagnostic, Location, OrcError, SourceError
from orc_rpl.syntax import nodes as n
from orc_rpl.world import World
from orc_rpl.world.online import ModelStore
from orc_rpl.transform.naming import Names, name_world


class TransformError(OrcError):
    """A program or world the transformation cannot map (the message names the entity and why)."""


@dataclass(frozen=True)
class Job:
    """One program and its world on their way between the representations; every pass returns a new Job."""

    program: n.Program
    world: World
    path: str = "<program>"                                    #: the program file, for messages
    source: str | None = None                                  #: its text, for carets
    names: Names | None = None                                 #: on-line names of the world's entities
    used: tuple[str, ...] = ()                                 #: entities the program refers to, in first-use order
    chains: Mapping[str, tuple[str, ...]] = field(default_factory=lambda: MappingProxyType({}))  #: on-line name -> FRAME nesting
    store: ModelStore | None = None                            #: the model attributes kept off-line (after reduce_world)

    def named(self) -> Job:
        """The job with the world's on-line names computed."""
        if self.names is not None:
            return self
        return Job(self.program, self.world, self.path, self.source, name_world(self.world), self.used, self.chains, self.store)

    def error(self, node: n.Node, message: str, hint: str = "") -> SourceError:
        """A SourceError at a node of the program."""
        span = node.span
        location = Location(self.path, span.line or 1, span.column or 1, span.end_line, span.end_column)
        return SourceError([Diagnostic(location, message, hint)], self.source)
