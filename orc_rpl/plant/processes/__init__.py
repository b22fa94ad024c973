"""Process models of the simulated cell (thesis 4.5): equipment that answers the robot's outputs with inputs."""

from __future__ import annotations

from orc_rpl.plant.processes.parts import PartSupply, Pick
from orc_rpl.plant.processes.weld_gun import Weld, WeldGunProcess

__all__ = ["PartSupply", "Pick", "Weld", "WeldGunProcess"]
