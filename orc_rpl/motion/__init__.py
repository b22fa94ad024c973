"""The motion layer: move(), planning, blending, actions, stops and modes (thesis 4.3-4.5, 5.2)."""

from __future__ import annotations

from orc_rpl.motion.actions import ActionSlot, Actions, MotionData, MoveSignal, until
from orc_rpl.motion.backend import Backend, KinematicBackend
from orc_rpl.motion.handle import MoveHandle
from orc_rpl.motion.kinematics import ArmLike, Kinematics
from orc_rpl.motion.layer import MotionLayer
from orc_rpl.motion.specs import (
    DEFAULT_PARAMS,
    FINE,
    CartesianMotion,
    Computation,
    FuncParams,
    FunctionMotion,
    JointMotion,
    Known,
    Mode,
    Motion,
    MoveStatus,
    Params,
)
from orc_rpl.motion.virtual import ServoBackend, make_virtual_motion_layer

__all__ = [
    "DEFAULT_PARAMS", "FINE", "ActionSlot", "Actions", "ArmLike", "Backend", "CartesianMotion", "Computation",
    "FuncParams", "FunctionMotion", "JointMotion", "KinematicBackend", "Kinematics", "Known", "Mode", "Motion",
    "MotionData", "MotionLayer", "MoveHandle", "MoveSignal", "MoveStatus", "Params", "ServoBackend",
    "make_virtual_motion_layer", "until",
]
