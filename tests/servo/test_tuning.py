"""Task-specific servo tunings (thesis 2.4): per-joint gains and feed-forward corrections, switched without a bump."""

from __future__ import annotations

import numpy as np
import pytest

from orc_rpl.errors import UsageError
from orc_rpl.servo import JointServo, ServoGains, ServoLoop, ServoTuning

pytestmark = pytest.mark.sim

N = 6


def tuning(kp: float = 40.0, bw: float = 160.0, wi: float = 15.0, d_offset: tuple[float, ...] = (0.0,) * N,
           d_inertia: tuple[float, ...] = (0.0,) * N) -> ServoTuning:
    return ServoTuning((kp,) * N, (bw,) * N, (wi,) * N, d_inertia, (0.0,) * N, d_offset, "tuning(test)")


def _torques(loop: ServoLoop, steps: int) -> np.ndarray:
    q0 = loop.arm.home_q
    out = []
    for k in range(steps):
        t = k * 0.001
        q_ref = q0 + 0.2 * np.sin(3.0 * t)
        qd_ref = np.full(N, 0.6 * np.cos(3.0 * t))
        qdd_ref = np.full(N, -1.8 * np.sin(3.0 * t))
        out.append(loop.run(q_ref, qd_ref, qdd_ref, 1).tau)
    return np.array(out)


def test_a_tuning_with_the_default_gains_gives_the_plain_law_to_the_last_bit() -> None:
    plain, tuned = ServoLoop(), ServoLoop()
    for loop in (plain, tuned):
        loop.reset(loop.arm.home_q)
    tuned.set_tuning(tuning())
    assert np.array_equal(_torques(plain, 400), _torques(tuned, 400))


def test_restoring_the_default_gives_back_the_plain_law_and_its_gains() -> None:
    loop = ServoLoop()
    loop.reset(loop.arm.home_q)
    servo = loop.servo
    plain_update = servo.update
    loop.set_tuning(tuning(kp=60.0, bw=240.0))
    assert servo.tuning is not None and servo.update != plain_update
    assert np.all(servo._kp == 60.0) and np.all(servo._velocity_bw == 240.0)
    loop.set_tuning(None)
    assert servo.tuning is None and servo.update.__func__ is JointServo.update  # type: ignore[attr-defined]
    g = ServoGains()
    assert np.all(servo._kp == g.position_gain_1_s) and np.all(servo._velocity_bw == g.velocity_bw_rad_s)


def _holding_an_unknown_payload() -> tuple[ServoLoop, np.ndarray]:
    """A loop at home holding 12 kg its model does not know, after the integral has taken the weight."""
    loop = ServoLoop()
    q0 = loop.arm.home_q
    loop.reset(q0)
    loop.set_payload(12.0, known=False)
    loop.hold(q0, 1500)  # the integral has taken the payload's weight
    return loop, q0


def test_switching_to_a_tuning_that_carries_the_payload_weight_does_not_bump() -> None:
    loop, q0 = _holding_an_unknown_payload()
    weight = loop.servo.integral.copy()
    before = loop.hold(q0, 1).tau
    loop.set_tuning(tuning(d_offset=tuple(weight)))
    after = loop.hold(q0, 1).tau
    assert np.allclose(before, after, atol=0.05), "bumpless: the feed-forward takes over from the integral"
    assert np.allclose(loop.servo.integral, 0.0, atol=0.05)
    loop.set_tuning(None)
    assert np.allclose(loop.hold(q0, 1).tau, before, atol=0.05), "and gives it back"


def test_a_tuning_with_a_load_feeds_its_weight_forward_at_every_pose_without_a_bump() -> None:
    import dataclasses

    loop, q0 = _holding_an_unknown_payload()
    before = loop.hold(q0, 1).tau
    loop.set_tuning(dataclasses.replace(tuning(), load_kg=12.0))
    after = loop.hold(q0, 1).tau
    assert np.allclose(before, after, atol=0.05), "bumpless: the load's weight taken over from the integral"
    assert np.allclose(loop.servo.integral, 0.0, atol=0.5), "the model's payload now holds the part"
    assert loop.servo.arm.payload[0] == 12.0
    loop.servo.set_control_payload(3.0)  # a motion's LOAD adds to the tuning's load
    assert loop.servo.arm.payload[0] == 15.0
    loop.servo.set_control_payload(0.0)
    loop.set_tuning(None)
    assert loop.servo.arm.payload[0] == 0.0
    assert np.allclose(loop.hold(q0, 1).tau, before, atol=0.05), "and gives it back"


def test_a_tuning_scales_the_friction_fed_forward() -> None:
    import dataclasses

    loop = ServoLoop()
    loop.reset(loop.arm.home_q)
    loop.servo.set_friction((10.0,) * N, (2.0,) * N)
    loop.set_tuning(dataclasses.replace(tuning(), friction_factor=(2.0,) + (1.0,) * (N - 1)))
    assert loop.servo._coulomb[0] == 20.0 and loop.servo._viscous[0] == 4.0 and loop.servo._coulomb[1] == 10.0
    loop.set_tuning(None)
    assert loop.servo._coulomb[0] == 10.0 and loop.servo.friction()[0][0] == 10.0
    with pytest.raises(UsageError):
        dataclasses.replace(tuning(), friction_factor=(1.0,) * 3)


def test_the_inertia_correction_adds_to_the_feed_forward() -> None:
    plain, tuned = ServoLoop(), ServoLoop()
    for loop in (plain, tuned):
        loop.reset(loop.arm.home_q)
    tuned.set_tuning(tuning(d_inertia=(2.0,) + (0.0,) * (N - 1)))
    q0, zero, qdd = plain.arm.home_q, np.zeros(N), np.array([1.0, 0, 0, 0, 0, 0])
    a, b = plain.run(q0, zero, qdd, 1).tau, tuned.run(q0, zero, qdd, 1).tau
    assert b[0] - a[0] == pytest.approx(2.0, abs=1e-9) and np.array_equal(a[1:], b[1:])


@pytest.mark.parametrize("fields", [dict(position_gain_1_s=(1.0,) * 5), dict(velocity_bw_rad_s=(-1.0,) * N),
                                    dict(d_offset_nm=(float("nan"),) * N)])
def test_malformed_tunings_are_refused(fields: dict[str, tuple[float, ...]]) -> None:
    base = dict(position_gain_1_s=(40.0,) * N, velocity_bw_rad_s=(160.0,) * N, integral_bw_rad_s=(15.0,) * N,
                d_inertia_kg_m2=(0.0,) * N, d_viscous_nm_s=(0.0,) * N, d_offset_nm=(0.0,) * N)
    with pytest.raises(UsageError):
        ServoTuning(**{**base, **fields})  # type: ignore[arg-type]


def test_a_tuning_for_another_arm_is_refused() -> None:
    loop = ServoLoop()
    with pytest.raises(UsageError, match="7 joints"):
        loop.set_tuning(ServoTuning((1.0,) * 7, (1.0,) * 7, (1.0,) * 7, (0.0,) * 7, (0.0,) * 7, (0.0,) * 7))
