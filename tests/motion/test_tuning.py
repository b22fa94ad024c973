"""Params.tuning reaches the servo for its motion only (thesis 2.4: MOVE ... WITH TUNING = t)."""

from __future__ import annotations

import numpy as np
import pytest

from orc_rpl.motion import JointMotion, MotionLayer, Params
from orc_rpl.servo import ServoTuning

N = 6
FAST = ServoTuning((60.0,) * N, (240.0,) * N, (15.0,) * N, (0.0,) * N, (0.0,) * N, (0.0,) * N, "tuning(fast)")


@pytest.mark.sim
def test_a_tuning_holds_for_its_motion_only(servo: MotionLayer) -> None:
    servo_law = servo.backend.loop.servo  # type: ignore[attr-defined]
    home = np.array(servo.kin.arm.home_q)
    seen: list[object] = []
    h = servo.move(JointMotion(tuple(home + 0.1)), Params(tuning=FAST))
    while not h.done:
        servo.tick()
        seen.append(servo_law.tuning)
    assert seen[0] is FAST and seen[-2] is FAST, "from the motion's first cycle through its settling"
    assert servo_law.tuning is None and np.all(servo_law._velocity_bw == 160.0), "default gains after the motion"
    h = servo.move(JointMotion(tuple(home)), Params())
    while not h.done:
        servo.tick()
        assert servo_law.tuning is None


@pytest.mark.sim
def test_a_stopped_tuned_motion_gives_the_default_gains_back(servo: MotionLayer) -> None:
    home = np.array(servo.kin.arm.home_q)
    h = servo.move(JointMotion(tuple(home + 0.3)), Params(tuning=FAST))
    servo.run_for(0.1)
    assert servo.backend.loop.servo.tuning is FAST  # type: ignore[attr-defined]
    servo.stop_move()
    servo.wait(h)
    assert servo.backend.loop.servo.tuning is None  # type: ignore[attr-defined]


def test_the_kinematic_robot_records_a_tuning_and_moves_as_without(kinematic: MotionLayer) -> None:
    home = np.array(kinematic.kin.arm.home_q)
    h = kinematic.move(JointMotion(tuple(home + 0.1)), Params(tuning=FAST))
    kinematic.wait(h)
    assert h.params.tuning is FAST and np.allclose(kinematic.current_q(), home + 0.1)


@pytest.mark.sim
def test_a_moves_load_reaches_the_servos_feed_forward(servo: MotionLayer) -> None:
    loop = servo.backend.loop  # type: ignore[attr-defined]
    home = np.array(servo.kin.arm.home_q)
    servo.wait(servo.move(JointMotion(tuple(home + 0.05)), Params(load_kg=10.0)))
    assert loop.servo.arm.payload[0] == 10.0, "thesis 4.5: the load in Par reaches the control"
    servo.wait(servo.move(JointMotion(tuple(home)), Params()))
    assert loop.servo.arm.payload[0] == 0.0
