"""Tests of local control: holding under gravity, settling after a step, tracking with feed-forward."""

from __future__ import annotations

import math

import numpy as np
import pytest

from orc_rpl.errors import UsageError
from orc_rpl.servo import ServoGains, ServoLoop

pytestmark = pytest.mark.sim

FINE_MM, FINE_DEG = 0.5, 0.1


def _tcp_miss(loop: ServoLoop, q: np.ndarray, q_target: np.ndarray) -> tuple[float, float]:
    """TCP position error (mm) and largest joint error (deg)."""
    arm = loop.arm
    miss_m = np.linalg.norm(arm.fk(q)[:3, 3] - arm.fk(q_target)[:3, 3])
    return 1000.0 * float(miss_m), math.degrees(float(np.abs(q - q_target).max()))


@pytest.mark.parametrize("robot", ["irb2400", "ur5e"])
def test_servo_holds_a_pose_under_gravity(robot: str) -> None:
    loop = ServoLoop(robot)
    q0 = loop.arm.home_q + 0.2
    loop.reset(q0)
    state = loop.hold(q0, 500)
    mm, deg = _tcp_miss(loop, state.q, q0)
    assert mm < 1e-6 and deg < 1e-6, "feed-forward is the plant's own model: nothing should move"


@pytest.mark.parametrize("robot", ["irb2400", "ur5e"])
def test_servo_settles_after_a_small_step(robot: str) -> None:
    loop = ServoLoop(robot)
    q0 = loop.arm.home_q
    q1 = q0 + np.radians([1.0, -1.0, 1.0, 2.0, -2.0, 2.0])
    loop.reset(q0)
    state = loop.hold(q1, 300)
    mm, deg = _tcp_miss(loop, state.q, q1)
    assert mm < FINE_MM and deg < FINE_DEG, f"FINE within 300 ms: {mm:.3f} mm, {deg:.4f} deg"


def test_unknown_payload_is_corrected_by_the_integral() -> None:
    loop = ServoLoop()
    q0 = loop.arm.home_q
    loop.reset(q0)
    loop.set_payload(10.0, known=False)
    state = loop.hold(q0, 800)
    mm, deg = _tcp_miss(loop, state.q, q0)
    assert mm < FINE_MM and deg < FINE_DEG, f"integral action against an unmodelled 10 kg: {mm:.3f} mm"


def _trapezoid(q0: np.ndarray, q1: np.ndarray, duration_s: float):
    """Synchronised constant-acceleration profile: accelerate a third, coast a third, brake a third."""
    ta = duration_s / 3
    v = (q1 - q0) / (duration_s - ta)
    a = v / ta

    def ref(t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        if t < ta:
            return q0 + 0.5 * a * t * t, a * t, a
        if t < duration_s - ta:
            return q0 + 0.5 * a * ta * ta + v * (t - ta), v, 0 * a
        if t < duration_s:
            r = duration_s - t
            return q1 - 0.5 * a * r * r, a * r, -a
        return q1, 0 * a, 0 * a

    return ref


def test_irb2400_tracks_a_fast_joint_move_and_stops_fine() -> None:
    loop = ServoLoop()
    arm = loop.arm
    q0 = arm.home_q
    q1 = q0 + np.radians([90, 30, -40, 90, -60, 180])
    # 1.05 s: the slowest joint (j6, 180 deg) near its speed and acceleration limits.
    ref = _trapezoid(q0, q1, 1.05)
    loop.reset(q0)
    worst_rad = 0.0
    while loop.time_s < 1.05:
        state = loop.run(*ref(loop.time_s), n_steps=4)
        worst_rad = max(worst_rad, float(np.abs(state.position_error).max()))
    assert math.degrees(worst_rad) < 0.1, "tracking error along the move (deg)"
    state = loop.hold(q1, 100)
    mm, deg = _tcp_miss(loop, state.q, q1)
    assert mm < FINE_MM and deg < FINE_DEG, f"FINE 100 ms after the reference stops: {mm:.3f} mm, {deg:.4f} deg"


def test_per_step_references_are_accepted() -> None:
    loop = ServoLoop()
    q = np.tile(loop.arm.home_q, (4, 1))
    zero = np.zeros((4, 6))
    state = loop.run(q, zero, zero, n_steps=4)
    assert state.time_s == pytest.approx(0.004)


def test_bad_references_are_usage_errors() -> None:
    loop = ServoLoop()
    with pytest.raises(UsageError, match="NaN"):
        loop.run(np.full(6, math.nan), np.zeros(6), np.zeros(6))
    with pytest.raises(UsageError, match="6 values"):
        loop.run(np.zeros(5), np.zeros(5), np.zeros(5))
    with pytest.raises(UsageError, match="velocity_bw"):
        ServoGains(velocity_bw_rad_s=-1.0)


def test_motion_layer_calls_on_the_arm_do_not_change_the_feed_forward() -> None:
    loop = ServoLoop()
    q0 = loop.arm.home_q
    loop.reset(q0)
    loop.set_payload(10.0)
    zero = np.zeros(6)
    loop.arm.inverse_dynamics(q0, zero, zero, payload_kg=0.0)  # a planner's query without payload
    state = loop.hold(q0, 50)
    mm, _ = _tcp_miss(loop, state.q, q0)
    assert mm < 1e-6, "the servo keeps its own model with the 10 kg payload"


def test_logger_attached_to_the_loop_samples_at_the_chosen_rate() -> None:
    from orc_rpl.signals import Logger

    loop = ServoLoop()
    logger = Logger(lambda: loop.time_s)
    loop.attach_logger(logger, every_steps=4)
    loop.hold(loop.arm.home_q, 40)
    rec = logger.recording()
    assert len(rec) == 10 and rec["tcp"].shape == (10, 3)
    np.testing.assert_allclose(rec.time_s, 0.001 + 0.004 * np.arange(10))


def test_torque_offset_pushes_the_joint_against_its_servo() -> None:
    loop = ServoLoop()
    q0 = loop.arm.home_q
    loop.reset(q0)
    loop.set_torque_offset([0, 0, 0, 0, 0, 5.0])
    state = loop.hold(q0, 20)
    assert state.q[5] > q0[5], "the offset turns j6 before the loops catch it"
    assert loop.servo.torque[5] < 5.0, "and the loops answer"


def _plain_law(servo, state: dict, q_ref, qd_ref, qdd_ref, q, qd) -> np.ndarray:
    """The servo law written plainly (allocating numpy expressions): the reference the fast update must equal."""
    g, arm = servo.gains, servo.arm
    if state["steps"] % g.inertia_every_steps == 0:
        state["kv"] = arm.mass_matrix_diagonal_unchecked(q) * g.velocity_bw_rad_s
        state["ki_dt"] = state["kv"] * (g.integral_bw_rad_s * servo.period_s)
    state["steps"] += 1
    velocity_error = qd_ref - qd
    velocity_error += g.position_gain_1_s * (q_ref - q)
    integral = state["integral"] + state["ki_dt"] * velocity_error
    integral = np.maximum(np.minimum(integral, servo._integral_max), -servo._integral_max)
    demand = state["kv"] * velocity_error
    demand += arm.inverse_dynamics_unchecked(q_ref, qd_ref, qdd_ref)
    demand += integral
    demand += servo.torque_offset
    tau = np.maximum(np.minimum(demand, servo._tau_max), -servo._tau_max)
    state["integral"] = np.where(tau != demand, state["integral"], integral)
    return tau


def test_servo_update_equals_the_plain_law_to_the_last_bit() -> None:
    loop = ServoLoop()
    servo, rng = loop.servo, np.random.default_rng(7)
    servo.torque_offset = rng.normal(0.0, 20.0, 6)
    state = {"steps": 0, "integral": np.zeros(6), "kv": None, "ki_dt": None}
    q0 = loop.arm.home_q
    saturated = 0
    for k in range(200):
        # errors large enough now and then to saturate the motors and wind the integral against its limit
        spread = 0.5 if k % 10 == 0 else 0.01
        q_ref, q = q0 + rng.normal(0.0, 0.3, 6), q0 + rng.normal(0.0, spread, 6)
        qd_ref, qd, qdd_ref = rng.normal(0.0, 1.0, 6), rng.normal(0.0, 1.0, 6), rng.normal(0.0, 5.0, 6)
        expected = _plain_law(servo, state, q_ref, qd_ref, qdd_ref, q, qd)
        tau = servo.update(q_ref, qd_ref, qdd_ref, q, qd)
        assert np.array_equal(tau, expected), f"step {k}: the fast law differs from the plain one"
        assert np.array_equal(servo.integral, state["integral"]), f"step {k}: integral (anti-windup) differs"
        saturated += int(servo.saturated.any())
    assert saturated > 0, "the case should exercise saturation and the anti-windup"


def test_a_single_reference_is_continued_exactly_as_per_step_references() -> None:
    one, steps = ServoLoop(), ServoLoop()
    q0, qd0, qdd0 = one.arm.home_q + 0.05, np.full(6, 0.3), np.full(6, -0.8)
    rows = []
    for k in range(4):
        t = k * one.period_s  # the constant-acceleration continuation, one step at a time
        rows.append((q0 + qd0 * t + (0.5 * t * t) * qdd0 if k else q0, qd0 + qdd0 * t if k else qd0, qdd0))
    a = one.run(q0, qd0, qdd0, n_steps=4)
    b = steps.run(*(np.array(column) for column in zip(*rows)), n_steps=4)
    assert np.array_equal(a.q, b.q) and np.array_equal(a.qd, b.qd) and np.array_equal(a.tau, b.tau)
