"""Helpers for pendant tests: a synchronous session on a copy of a program, on the fast kinematic robot."""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np

from orc_rpl.pendant.robot import PendantRobot
from orc_rpl.pendant.session import PendantSession
from orc_rpl.world.pose import Pose

#: The thesis' section 7.3 program (programs/online/thesis_7_3_online_frame.rpl), with the frame rotated
#: 90 degrees about z so that a position read in the wrong frame is far away *and* turned.
FRAME_PROGRAM = textwrap.dedent("""\
    FRAME base_plate = POSE(900mm, 0, 500mm, 90deg, 0, 0)
    POS pos0 = POSE(800mm, -300mm, 800mm, 0, 180deg, 0)
    POS pos1 = POSE(100mm, -100mm, 50mm, 0, 180deg, 0) IN base_plate
    POS pos2 = POSE(100mm, 100mm, 50mm, 0, 180deg, 0) IN base_plate
    POS pos3 = POSE(800mm, 300mm, 800mm, 0, 180deg, 0)

    MOVE ARM TO pos0
    FRAME base_plate
        MOVE ARM TO pos1
        MOVE ARM TO pos2
    ENDFRAME
    MOVE ARM TO pos3
    """)

#: Lines of FRAME_PROGRAM.
LINE_MOVE_POS0, LINE_FRAME, LINE_MOVE_POS1, LINE_MOVE_POS2, LINE_ENDFRAME, LINE_MOVE_POS3 = 7, 8, 9, 10, 11, 12


def session_on(tmp_path: Path, text: str = FRAME_PROGRAM, name: str = "cell.rpl", **options: object) -> PendantSession:
    """A synchronous session on `text` saved as tmp_path/name (so the journal and :save have a home)."""
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    robot = PendantRobot.virtual(backend="kinematic")
    return PendantSession(path, robot=robot, **options)  # type: ignore[arg-type]


def world_of(frame: Pose, pose: Pose) -> np.ndarray:
    """The world position (m) of `pose` given relative to `frame`."""
    return (frame.matrix() @ pose.matrix())[:3, 3]


def tcp_m(session: PendantSession) -> np.ndarray:
    """Where the TCP of the session's tool is, world, m."""
    return np.array([getattr(session.robot.tcp_pose(session.execution.tool_pose()), a) for a in "xyz"])
