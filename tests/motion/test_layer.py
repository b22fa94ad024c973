"""The motion layer on the virtual robot: FINE accuracy, determinism, actions and T_d, stops, blending, errors."""

from __future__ import annotations

import math

import numpy as np
import pytest

from orc_rpl.errors import JointLimit, Unreachable, UsageError
from orc_rpl.motion import (
    Actions,
    CartesianMotion,
    Computation,
    FunctionMotion,
    JointMotion,
    Mode,
    MotionLayer,
    MoveStatus,
    Params,
    make_virtual_motion_layer,
    until,
)
from orc_rpl.world.pose import Pose

from .motion_helpers import pose_here, tcp_error

pytestmark = pytest.mark.sim


def test_fine_targets_are_reached_within_half_a_millimetre_and_a_tenth_of_a_degree(servo: MotionLayer) -> None:
    q0 = servo.current_q()
    joint_q = q0 + np.array([0.6, 0.3, -0.2, 0.5, -0.4, 0.8])
    h = servo.move(JointMotion(tuple(joint_q)))
    servo.wait(h)
    target = Pose.from_matrix(servo.fk(joint_q))
    assert h.settled and tcp_error(servo, target)[0] < 0.5 and tcp_error(servo, target)[1] < 0.1
    for motion in (
        CartesianMotion(pose_here(servo, 0.1, -0.3, -0.25)),
        CartesianMotion(pose_here(servo, 0.0, 0.4, 0.0), "circular", via=pose_here(servo, 0.15, 0.2, 0.0)),
    ):
        h = servo.move(motion)
        servo.wait(h)
        pos_mm, rot_deg = tcp_error(servo, motion.target)
        assert h.status is MoveStatus.READY and h.settled
        assert pos_mm < 0.5, f"{motion.kind} move ends {pos_mm:.3f} mm from its FINE target (0.5 mm allowed)"
        assert rot_deg < 0.1, f"{motion.kind} move ends {rot_deg:.4f} deg from its FINE target (0.1 deg allowed)"


def _program(layer: MotionLayer) -> np.ndarray:
    trace: list[np.ndarray] = []
    acts = Actions(continuous=[lambda d, slot: trace.append(np.concatenate([[d.time_s], d.q, d.torque]))])
    q0 = layer.current_q()
    layer.move(JointMotion(tuple(q0 + 0.3)), Params(zone_m=0.05), acts)
    layer.run_until_idle()
    layer.move(CartesianMotion(pose_here(layer, 0.0, 0.2, -0.1)), Params(zone_m=0.02))
    layer.move(CartesianMotion(pose_here(layer, -0.1, 0.2, -0.1)))
    layer.run_until_idle()
    return np.array(trace)


def test_two_runs_give_identical_recordings() -> None:
    a = _program(make_virtual_motion_layer(backend="servo", plant="ideal"))
    b = _program(make_virtual_motion_layer(backend="servo", plant="ideal"))
    assert a.shape == b.shape and len(a) > 100
    assert np.array_equal(a, b), "the virtual robot is not deterministic: two runs of one program differ"


def test_action_signals_within_one_cycle_of_t_d_minus_tau(servo: MotionLayer) -> None:
    tau_s = 0.1

    def weld_signal(data, slot) -> None:  # type: ignore[no-untyped-def]
        if slot.signalled_at_s is None and data.time_s >= data.T_d - tau_s:
            slot.signal(data.T_d)

    acts = Actions(during=[weld_signal])
    h = servo.move(JointMotion(tuple(servo.current_q() + 0.25)), Params(), acts)
    assert servo.wait(h.signal)
    assert h.signal.last_reason == "weld_signal" and not h.done
    fired = acts.slot("weld_signal").signalled_at_s
    t_d = acts.result("weld_signal")
    assert t_d - tau_s <= fired < t_d - tau_s + servo.dt_s + 1e-9, f"signal at {fired:.4f} s, wanted within one cycle after {t_d - tau_s:.4f} s"
    servo.wait(h)
    assert abs(h.t_end_s - t_d) < 1e-9


def test_linear_move_stays_on_the_straight_line(servo: MotionLayer) -> None:
    start = servo.tcp_pose()[:3, 3]
    target = pose_here(servo, 0.0, 0.5, -0.3)
    dev: list[float] = []
    end = target.matrix()[:3, 3]
    axis = (end - start) / np.linalg.norm(end - start)

    def deviation(data, slot) -> None:  # type: ignore[no-untyped-def]
        p = servo.kin.fk(data.q)[:3, 3] - start
        dev.append(float(np.linalg.norm(p - (p @ axis) * axis)))

    h = servo.move(CartesianMotion(target), Params(), Actions(during=[deviation]))
    servo.wait(h)
    assert max(dev) < 1e-3, f"the TCP leaves the straight line by {1000 * max(dev):.3f} mm (1 mm allowed)"


def test_stop_move_decelerates_on_the_path_and_returns_s(kinematic: MotionLayer) -> None:
    start = kinematic.tcp_pose()[:3, 3]
    target = pose_here(kinematic, 0.0, 0.6, 0.0)
    h = kinematic.move(CartesianMotion(target))
    kinematic.run_for(0.3)
    s = kinematic.stop_move()
    assert 0.0 < s < 1.0
    kinematic.wait(h)
    assert h.status is MoveStatus.ACT_STOPPED and h.stopped_s == pytest.approx(s)
    here = kinematic.tcp_pose()[:3, 3]
    end = target.matrix()[:3, 3]
    assert np.linalg.norm(here - (start + s * (end - start))) < 1e-4, "the robot did not stop where stop_move said"
    axis = (end - start) / np.linalg.norm(end - start)
    off = (here - start) - ((here - start) @ axis) * axis
    assert np.linalg.norm(off) < 1e-4, "braking left the path"
    rest = kinematic.path_left(h, s)
    h2 = kinematic.move(rest)
    kinematic.wait(h2)
    assert np.linalg.norm(kinematic.tcp_pose()[:3, 3] - end) < 1e-6


def test_until_condition_stops_the_move_and_reports_where(kinematic: MotionLayer) -> None:
    acts = until(lambda d: d.s >= 0.4)
    h = kinematic.move(CartesianMotion(pose_here(kinematic, 0.0, 0.5, 0.0)), Params(speed_m_s=0.2), acts)
    kinematic.wait(h)
    assert h.status is MoveStatus.ACT_STOPPED and h.stopped_by == "until"
    assert 0.4 <= h.stopped_s < 0.45, f"at 0.2 m/s the brake should stop within 2.5 cm; stopped at s={h.stopped_s:.3f}"
    assert acts.result("until") >= 0.4


@pytest.mark.parametrize(
    ("make", "error", "text"),
    [
        (lambda L: CartesianMotion(pose_here(L, 3.0, 0.0, 0.0)), Unreachable, "out of reach"),
        (lambda L: JointMotion(tuple(L.current_q() + np.array([0, 0, 2.0, 0, 0, 0]))), JointLimit, "joint 3"),
        (lambda L: JointMotion((0.0, math.nan, 0, 0, 0, 0)), UsageError, "finite"),
        (lambda L: CartesianMotion(Pose(math.nan, 0, 1)), UsageError, "finite"),
        (lambda L: JointMotion((0.0, 0.1)), UsageError, "6 joints"),
    ],
    ids=["unreachable", "joint_limit", "nan_joint", "nan_pose", "wrong_length"],
)
def test_bad_targets_raise_the_projects_errors(kinematic: MotionLayer, make, error, text) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(error, match=text):
        kinematic.move(make(kinematic))
    assert kinematic.idle()


def _corner_run(zone_m: float) -> tuple[float, float]:
    layer = make_virtual_motion_layer(backend="servo", plant="ideal")
    corner = pose_here(layer, 0.0, 0.4, 0.0)
    end = pose_here(layer, -0.3, 0.4, 0.0)
    speeds: list[tuple[float, float]] = []

    def watch(data, slot) -> None:  # type: ignore[no-untyped-def]
        p = layer.kin.fk(data.q)[:3, 3]
        v = layer.kin.arm.jacobian(data.q)[:3] @ data.qd
        speeds.append((float(np.linalg.norm(p - corner.matrix()[:3, 3])), float(np.linalg.norm(v))))

    layer.move(CartesianMotion(corner), Params(zone_m=zone_m), Actions(continuous=[watch]))
    h = layer.move(CartesianMotion(end), Params())
    layer.wait(h)
    closest = min(d for d, _ in speeds)
    near = [v for d, v in speeds if d < closest + 0.02]  # around the corner, where the blend passes it
    return layer.now_s(), min(near)


def test_zone_blending_does_not_stop_at_the_corner() -> None:
    t_fine, v_fine = _corner_run(0.0)
    t_zone, v_zone = _corner_run(0.05)
    assert v_fine < 0.01, "the FINE corner should stop"
    assert v_zone > 0.2, f"TCP speed near the blended corner drops to {v_zone:.3f} m/s (expected > 0.2)"
    assert t_zone < t_fine - 0.05, f"blended sequence takes {t_zone:.3f} s, FINE {t_fine:.3f} s"


def test_saved_plan_is_used_when_start_and_target_match(kinematic: MotionLayer) -> None:
    target = JointMotion(tuple(kinematic.current_q() + 0.2))
    saved = kinematic.move(target, Params(computation=Computation.SAVE, descriptor=7))
    assert saved.status is MoveStatus.READY and kinematic.idle()
    h = kinematic.move(target, Params(computation=Computation.DONE, descriptor=7))
    assert not h.replanned_during
    kinematic.wait(h)
    other = kinematic.move(JointMotion(tuple(kinematic.current_q() + 0.1)), Params(computation=Computation.DONE, descriptor=7))
    assert other.replanned_during, "a descriptor for another motion must fall back to planning during the move"
    kinematic.wait(other)


def test_moves_are_illegal_outside_run_and_track(kinematic: MotionLayer) -> None:
    kinematic.set_mode(Mode.STANDBY)
    assert kinematic.get_mode() is Mode.STANDBY
    assert kinematic.move(JointMotion(tuple(kinematic.current_q() + 0.1))).status is MoveStatus.ILLEGAL
    kinematic.set_mode(Mode.RUN)
    assert kinematic.move(JointMotion(tuple(kinematic.current_q() + 0.1))).status is MoveStatus.SPAWNED


def test_function_motion_follows_its_components(kinematic: MotionLayer) -> None:
    p = pose_here(kinematic)
    radius = 0.05
    motion = FunctionMotion(lambda s: p.x + radius * (1 - math.cos(2 * math.pi * s)), lambda s: p.y + radius * math.sin(2 * math.pi * s),
                            p.z, p.a, p.b, p.c)
    h = kinematic.move(motion)
    kinematic.wait(h)
    assert h.status is MoveStatus.READY
    assert np.linalg.norm(kinematic.tcp_pose()[:3, 3] - p.matrix()[:3, 3]) < 1e-6
