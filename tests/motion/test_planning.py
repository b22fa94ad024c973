"""Planned trajectories keep the joint, torque and TCP limits; TIME, zero-length moves, and toppra failures."""

from __future__ import annotations

import numpy as np
import pytest

from orc_rpl.errors import PlanningError
from orc_rpl.motion import CartesianMotion, FuncParams, JointMotion, MotionLayer, MoveStatus, Params
from orc_rpl.motion import timing
from orc_rpl.motion.planner import TORQUE_SHARE
from orc_rpl.world.pose import Pose

from .motion_helpers import pose_here

#: toppra's collocation holds the limits at grid points; between them the constant-acceleration
#: profile can exceed them slightly (measured: about 1 % for torque, velocity a bit more on curved paths)
MARGIN = 0.03


def _planned(layer: MotionLayer, motion, params: Params):  # type: ignore[no-untyped-def]
    h = layer.move(motion, params)
    traj = layer._traj
    assert traj is not None and h.status is MoveStatus.SPAWNED
    return traj


def _check_limits(layer: MotionLayer, traj, load_kg: float = 0.0) -> None:  # type: ignore[no-untyped-def]
    arm = layer.kin.arm
    qd = np.max(np.abs(traj.qd_f) / arm.qd_max)
    qdd = np.max(np.abs(traj.qdd_f) / arm.qdd_max)
    tau = max(float(np.max(np.abs(arm.inverse_dynamics(q, v, a, load_kg)) / (arm.tau_max * TORQUE_SHARE)))
              for q, v, a in zip(traj.q, traj.qd, traj.qdd))
    assert qd <= 1 + MARGIN, f"joint speed at {100 * qd:.1f} % of its limit (allowed {100 * (1 + MARGIN):.0f} %: toppra interpolation)"
    assert qdd <= 1 + MARGIN, f"joint acceleration at {100 * qdd:.1f} % of its limit (allowed {100 * (1 + MARGIN):.0f} %)"
    assert tau <= 1 + MARGIN, f"torque at {100 * tau:.1f} % of the planner's share (allowed {100 * (1 + MARGIN):.0f} %)"
    lo, hi = arm.q_min - 1e-9, arm.q_max + 1e-9
    assert np.all((traj.q_f >= lo) & (traj.q_f <= hi)), "a planned sample leaves the joint ranges"


@pytest.mark.parametrize(
    "name",
    ["joint", "joint_with_load", "linear", "circular"],
)
def test_planned_trajectory_respects_speed_acceleration_and_torque_limits(kinematic: MotionLayer, name: str) -> None:
    q0 = kinematic.current_q()
    load = 0.0
    if name.startswith("joint"):
        motion = JointMotion(tuple(q0 + np.array([1.2, 0.4, -0.3, 1.0, 0.6, 2.0])))
        load = 15.0 if name == "joint_with_load" else 0.0
    elif name == "linear":
        motion = CartesianMotion(pose_here(kinematic, -0.3, 0.5, -0.3))
    else:
        motion = CartesianMotion(pose_here(kinematic, 0.0, 0.4, -0.1), "circular", via=pose_here(kinematic, -0.15, 0.2, 0.0))
    traj = _planned(kinematic, motion, Params(load_kg=load))
    _check_limits(kinematic, traj, load)


def test_tcp_speed_limit_holds_along_a_line(kinematic: MotionLayer) -> None:
    traj = _planned(kinematic, CartesianMotion(pose_here(kinematic, 0.0, 0.6, -0.2)), Params(speed_m_s=0.25))
    tcp = np.array([kinematic.fk(q)[:3, 3] for q in traj.q])
    v = np.linalg.norm(np.diff(tcp, axis=0), axis=1) / traj.dt_s
    assert v.max() <= 0.25 * 1.01, f"TCP speed {v.max():.4f} m/s over the 0.25 m/s limit (1 % allowed)"
    assert v.max() >= 0.25 * 0.97, "the TCP never reaches its allowed speed: the profile is not time-optimal"


def test_speed_as_a_function_of_s_is_respected(kinematic: MotionLayer) -> None:
    params = FuncParams(speed_m_s=lambda s: 0.1 if s < 0.5 else 0.4)
    traj = _planned(kinematic, CartesianMotion(pose_here(kinematic, 0.0, 0.6, 0.0)), params)
    tcp = np.array([kinematic.fk(q)[:3, 3] for q in traj.q])
    v = np.linalg.norm(np.diff(tcp, axis=0), axis=1) / traj.dt_s
    first_half = traj.s[1:] < 0.45
    assert v[first_half].max() <= 0.1 * 1.02, "the slow first half runs faster than its FUNC speed"
    assert v.max() > 0.3, "the fast second half never speeds up"


def test_requested_time_stretches_the_motion(kinematic: MotionLayer) -> None:
    q0 = kinematic.current_q()
    h = kinematic.move(JointMotion(tuple(q0 + 0.2)), Params(time_s=2.0))
    kinematic.wait(h)
    assert abs((h.end_time_s - h.start_time_s) - 2.0) <= 0.0041, "the move does not take the requested 2 s (one cycle allowed)"


def test_zero_length_move_is_ready_at_once(kinematic: MotionLayer) -> None:
    h = kinematic.move(JointMotion(tuple(kinematic.current_q())))
    assert h.status is MoveStatus.READY and h.done and kinematic.idle()
    h = kinematic.move(CartesianMotion(pose_here(kinematic)))
    assert h.status is MoveStatus.READY and h.done


def test_toppra_failure_falls_back_to_a_conservative_profile(kinematic: MotionLayer, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(timing, "toppra_profile", lambda *a, **k: None)
    q0 = kinematic.current_q()
    h = kinematic.move(JointMotion(tuple(q0 + np.array([0.5, 0.2, -0.2, 0.3, 0.2, 0.5]))))
    _check_limits(kinematic, kinematic._traj)
    kinematic.wait(h)
    assert h.status is MoveStatus.READY
    assert np.allclose(kinematic.current_q(), q0 + np.array([0.5, 0.2, -0.2, 0.3, 0.2, 0.5]), atol=1e-9)


def test_collinear_circle_is_a_planning_error(kinematic: MotionLayer) -> None:
    with pytest.raises(PlanningError, match="on one line"):
        kinematic.move(CartesianMotion(pose_here(kinematic, 0, 0.2, 0), "circular", via=pose_here(kinematic, 0, 0.1, 0)))


def test_short_move_is_jerk_limited_and_ends_on_target(kinematic: MotionLayer) -> None:
    q0 = kinematic.current_q()
    target = q0 + np.array([0.02, -0.01, 0.015, 0.0, 0.02, 0.0])
    h = kinematic.short_move(JointMotion(tuple(target)))
    traj = kinematic._traj
    assert traj is not None and traj.kind == "short"
    jerk = np.abs(np.diff(traj.qdd_f, axis=0)) / (traj.dt_s / traj.sub)
    lim = kinematic.planner.short_limits(q0, Params())
    assert np.all(jerk <= lim.qddd_max * 1.01 + 1e-6), "short move exceeds its jerk limit"
    kinematic.wait(h)
    assert np.allclose(kinematic.current_q(), target, atol=1e-12)


def test_simulate_predicts_without_moving(kinematic: MotionLayer) -> None:
    q0 = kinematic.current_q()
    moves = [JointMotion(tuple(q0 + 0.3)), (CartesianMotion(Pose.from_matrix(kinematic.fk(q0 + 0.3)).offset(0, 0.2, 0)), Params())]
    sim = kinematic.simulate(moves)
    assert np.array_equal(kinematic.current_q(), q0) and kinematic.now_s() == 0.0
    for m in moves:
        kinematic.move(*(m if isinstance(m, tuple) else (m,)))
    kinematic.run_until_idle()
    assert sim.duration_s == pytest.approx(kinematic.now_s(), abs=1e-9)
    assert np.allclose(sim.q[-1], kinematic.current_q(), atol=1e-9)


def test_speed_cap_limits_joint_moves_at_the_tcp(kinematic: MotionLayer) -> None:
    kinematic.set_speed_cap(0.25)
    traj = _planned(kinematic, JointMotion(tuple(kinematic.current_q() + np.array([0.8, 0.3, -0.2, 0.5, -0.3, 1.0]))), Params())
    tcp = np.array([kinematic.fk(q)[:3, 3] for q in traj.q])
    v = np.linalg.norm(np.diff(tcp, axis=0), axis=1) / traj.dt_s
    assert v.max() <= 0.25 * 1.02, f"manual-mode cap exceeded: {v.max():.3f} m/s"


@pytest.mark.parametrize("cap_m_s", [0.25, 0.1])
def test_short_move_keeps_the_manual_tcp_speed_cap(kinematic: MotionLayer, cap_m_s: float) -> None:
    kinematic.set_speed_cap(cap_m_s)
    target = pose_here(kinematic, 0.0, 0.08, -0.05)
    h = kinematic.short_move(CartesianMotion(target))
    traj = kinematic._traj
    assert traj is not None and traj.kind == "short"
    tcp = np.array([kinematic.fk(q)[:3, 3] for q in traj.q_f])
    speed = np.linalg.norm(np.diff(tcp, axis=0), axis=1) / (traj.dt_s / traj.sub)
    assert speed.max() <= cap_m_s, f"short move TCP at {speed.max():.3f} m/s over the {cap_m_s} m/s cap (manual mode)"
    kinematic.wait(h)


def test_short_move_keeps_its_speed_attribute(kinematic: MotionLayer) -> None:
    h = kinematic.short_move(CartesianMotion(pose_here(kinematic, 0.0, 0.08, 0.0)), Params(speed_m_s=0.05))
    traj = kinematic._traj
    tcp = np.array([kinematic.fk(q)[:3, 3] for q in traj.q_f])
    speed = np.linalg.norm(np.diff(tcp, axis=0), axis=1) / (traj.dt_s / traj.sub)
    assert speed.max() <= 0.05, f"short move TCP at {speed.max():.3f} m/s over SPEED = 50mm/s"
    kinematic.wait(h)


def test_a_smoothed_trajectory_keeps_the_path_and_has_no_acceleration_steps(kinematic: MotionLayer) -> None:
    from orc_rpl.motion.trajectory import smoothed

    traj = _planned(kinematic, JointMotion((0.8, -0.4, 0.3, 0.5, 0.6, -0.7)), Params())
    h = traj.dt_s / traj.sub
    windows = (0.16, 0.13)
    smooth = smoothed(traj, windows)
    assert np.allclose(smooth.q_f, smooth.path(smooth.x_f)), "every reference on the path"
    assert smooth.x_f[0] == traj.x_f[0] and smooth.x_f[-1] == pytest.approx(traj.x_f[-1])
    assert smooth.sd_f[0] == 0.0 and smooth.sd_f[-1] == pytest.approx(0.0, abs=1e-9)
    assert smooth.exact_duration_s == pytest.approx(traj.exact_duration_s + sum(windows), abs=2 * h)
    assert np.all(np.diff(smooth.x_f) >= -1e-12), "never backwards"
    sdd, sdd_smooth = np.diff(traj.sd_f) / h, np.diff(smooth.sd_f) / h
    assert np.max(np.abs(sdd_smooth)) <= np.max(np.abs(sdd)) * 1.001, "no harder than the original"
    # the original's acceleration jumps (bang-bang); the average's changes by little from step to step
    assert np.max(np.abs(np.diff(sdd_smooth))) < 0.02 * np.max(np.abs(np.diff(sdd)))
    assert len(smooth.owner) == smooth.cycles + 1 and (len(smooth.x_f) - 1) == smooth.cycles * smooth.sub


@pytest.mark.parametrize("windows", [(0.164, 0.131), (0.123, 0.098)], ids=["whole periods", "three quarters of them"])
def test_an_averaged_trajectory_ends_exactly_where_its_path_ends(kinematic: MotionLayer,
                                                                windows: tuple[float, ...]) -> None:
    """The IRB 2400's elastic gears' windows (whole anti-resonance periods, and the 0.75 of them the layer uses): at
    the end s is 1 exactly (a belt target is met when the path ends; rounding left 0.999... until the FINE settling
    was over), never past the end; and with the layer's windows within the limits the unaveraged trajectory keeps
    (on a line the average mixes path accelerations from points where the path bends differently: measured 102.1 %
    of a joint's acceleration limit with these windows, 103.3 % with whole periods)."""
    from orc_rpl.motion.trajectory import smoothed

    for motion in (JointMotion((0.8, -0.4, 0.3, 0.5, 0.6, -0.7)), CartesianMotion(pose_here(kinematic, 0.2, 0.3, -0.1))):
        traj = _planned(kinematic, motion, Params())
        smooth = smoothed(traj, windows)
        assert smooth.x_f[-1] == traj.x_f[-1] and smooth.s[-1] == 1.0
        assert np.all(smooth.x_f <= traj.x_f[-1]), "never past the end"
        if windows == (0.123, 0.098):
            _check_limits(kinematic, smooth)
        kinematic.run_until_idle()


def test_the_owner_and_s_at_one_path_parameter_are_those_of_the_array_form_everywhere() -> None:
    from orc_rpl.motion.paths import DensePath
    from orc_rpl.motion.trajectory import SplinePath

    rng = np.random.default_rng(2)
    q = np.cumsum(rng.normal(size=(50, 6)), axis=0)
    owner = np.repeat([3, 4, 5], [20, 15, 15])
    s = np.concatenate([np.linspace(0.0, 1.0, 20), np.linspace(0.0, 1.0, 15), np.linspace(0.0, 1.0, 15)])
    path = SplinePath(DensePath(q, q[:, :3], owner, s))
    for x in np.concatenate([rng.uniform(-1.0, path.length + 1.0, 500), path.x_knots]).tolist():
        owners, ss = path.owner_and_s(np.array([x]))
        assert path.owner_and_s_at(x) == (int(owners[0]), float(ss[0]))
