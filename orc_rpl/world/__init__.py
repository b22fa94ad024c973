"""The world model: object tree, poses, frames, model/spatial/soft attributes, YAML I/O."""

from orc_rpl.world.objects import (FLANGE, ROBOT, ModelAttributes, OnlineFrame, PathAttribute, Position, RobotEntry,
                                   WorldError, WorldObject)
from orc_rpl.world.pose import WORLD, Pose
from orc_rpl.world.world import World, load_world, loads_world
from orc_rpl.world.online import ModelStore, restore_model_attributes, split_model_attributes

__all__ = [
    "FLANGE", "ROBOT", "WORLD", "ModelAttributes", "ModelStore", "OnlineFrame", "PathAttribute", "Pose", "Position", "RobotEntry",
    "World", "WorldError", "WorldObject", "load_world", "loads_world", "restore_model_attributes", "split_model_attributes",
]
