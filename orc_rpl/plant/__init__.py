"""What the servos drive: the MuJoCo cell; serial links."""

from __future__ import annotations

from typing import Any

from orc_rpl.plant.cell import Box, CellDescription, build_spec, default_cell, table
from orc_rpl.plant.io import CellIO, Channels

__all__ = ["Box", "CellDescription", "CellIO", "Channels", "SimCell", "build_spec", "default_cell", "table"]


def __getattr__(name: str) -> Any:
    # SimCell imports MuJoCo: only when someone asks for it.
    if name == "SimCell":
        from orc_rpl.plant.sim import SimCell

        return SimCell
    raise AttributeError(f"module 'orc_rpl.plant' has no attribute {name!r}")
