"""The adaptive feed-forward: friction and payload the model lacks, learnt from the servo's integral."""

from __future__ import annotations

import numpy as np
import pytest

from orc_rpl.robot import load_robot
from orc_rpl.robot.plants import plant_spec
from orc_rpl.servo.adaptation import FeedForwardAdaptation
from orc_rpl.servo.control import FRICTION_SMOOTH_RAD_S, JointServo


def test_the_estimate_learns_friction_and_payload_and_the_integral_hands_them_over() -> None:
    arm, spec = load_robot("irb2400"), plant_spec("irb2400")
    servo = JointServo(arm)
    servo.set_friction(spec.coulomb_nm, spec.viscous_nm_s)
    model = servo.arm
    adaptation = FeedForwardAdaptation(servo, spec.coulomb_nm, spec.viscous_nm_s, lambda q: model.jacobian(q)[:3])
    d_coulomb, d_viscous = np.array([48.0, 60.0, 30.0, 2.0, 2.0, 1.0]), np.array([50.0, 50.0, 25.0, 2.0, 2.0, 1.0])
    payload_kg = 6.5
    rng = np.random.default_rng(0)
    for _ in range(3000):   # 12 s of motion cycles at varied poses and speeds
        q = np.array(arm.home_q) + rng.uniform(-0.8, 0.8, 6)
        qd = rng.uniform(-1.5, 1.5, 6)
        missing = (d_coulomb * np.tanh(qd / FRICTION_SMOOTH_RAD_S) + d_viscous * qd
                   + payload_kg * 9.81 * model.jacobian(q)[2])
        # the feedback's integral carries what the feed-forward lacks: all of it less what the estimate adds
        servo.integral = missing - adaptation._added
        adaptation.update(q, qd)
    theta = adaptation.theta
    assert np.allclose(theta[:3], d_coulomb[:3], rtol=0.05)
    assert np.allclose(theta[6:9], d_viscous[:3], rtol=0.05)
    assert abs(theta[12] - payload_kg) < 0.2
    assert servo.arm.payload[0] == pytest.approx(theta[12]), "the payload is in the servo's model (none declared)"
    assert np.allclose(servo._coulomb, np.array(spec.coulomb_nm) + theta[:6]), "the estimate is in the feed-forward"
