"""Robot models, shared below servo and plant: MJCF descriptions, the Pinocchio model (FK, IK, dynamics), limits."""

from orc_rpl.robot.ik import IkSettings, solve_ik
from orc_rpl.robot.model import ArmModel, load_robot
from orc_rpl.robot.robots import ROBOTS, RobotRegistry, RobotSpec, worlds_dir

__all__ = ["ArmModel", "IkSettings", "ROBOTS", "RobotRegistry", "RobotSpec", "load_robot", "solve_ik", "worlds_dir"]
