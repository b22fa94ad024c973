"""Arm control: Pinocchio model (FK, IK, dynamics), limits, path velocity control."""

from orc_rpl.arm.ik import IkSettings, solve_ik
from orc_rpl.arm.model import ArmModel
from orc_rpl.arm.robots import ROBOTS, RobotRegistry, RobotSpec, load_robot, worlds_dir

__all__ = ["ArmModel", "IkSettings", "ROBOTS", "RobotRegistry", "RobotSpec", "load_robot", "solve_ik", "worlds_dir"]
