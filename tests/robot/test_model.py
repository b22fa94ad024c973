"""Tests of the arm model: kinematics, dynamics against MuJoCo, limits and input checks."""

from __future__ import annotations

import math

import numpy as np
import pytest

from orc_rpl.robot import ROBOTS, RobotRegistry, load_robot
from orc_rpl.errors import JointLimit, UsageError
from orc_rpl.world.pose import matrix

ROBOT_NAMES = ["irb2400", "ur5e", "so101"]


@pytest.fixture(scope="module", params=ROBOT_NAMES)
def arm(request: pytest.FixtureRequest):
    return load_robot(request.param)


def test_both_robots_are_registered_and_irb2400_is_the_default() -> None:
    assert set(ROBOT_NAMES) <= set(ROBOTS.names())
    assert load_robot().name == "irb2400"


def test_unknown_robot_names_the_known_ones() -> None:
    with pytest.raises(UsageError, match="unknown robot 'kuka'.*irb2400, so101, ur5e"):
        load_robot("kuka")


def test_registry_refuses_a_duplicate_name() -> None:
    registry = RobotRegistry()
    spec = ROBOTS.get("ur5e")
    registry.register(spec)
    with pytest.raises(UsageError, match="already registered"):
        registry.register(spec)


def test_irb2400_zero_configuration_matches_the_published_kinematics() -> None:
    arm = load_robot("irb2400")
    t = arm.fk(np.zeros(6))
    # Flange at 0.100+0.258+0.497+0.085 forward, 0.615+0.705+0.135 up; tool0 z forward, x down.
    np.testing.assert_allclose(t[:3, 3], [0.940, 0.0, 1.455], atol=1e-12)
    np.testing.assert_allclose(t[:3, :3], [[0, 0, 1], [0, 1, 0], [-1, 0, 0]], atol=1e-12)


def test_irb2400_positive_j2_tilts_the_arm_forward_and_down() -> None:
    arm = load_robot("irb2400")
    q = np.zeros(6)
    q[1] = math.radians(10)
    p0, p1 = arm.fk(np.zeros(6))[:3, 3], arm.fk(q)[:3, 3]
    assert p1[0] > p0[0] and p1[2] < p0[2]


def test_ur5e_zero_configuration_matches_universal_robots_dh() -> None:
    t = load_robot("ur5e").fk(np.zeros(6))
    np.testing.assert_allclose(t[:3, 3], [-0.8172, -0.2329, 0.0628], atol=1e-12)


def test_tool_moves_the_tcp_along_flange_z(arm) -> None:
    tool = matrix(0, 0, 0.3)
    t = arm.fk(arm.home_q, tool)
    flange = arm.fk(arm.home_q)
    np.testing.assert_allclose(t[:3, 3], flange[:3, 3] + 0.3 * flange[:3, 2], atol=1e-12)


def test_jacobian_matches_finite_differences_at_the_tcp(arm) -> None:
    tool = matrix(0.02, -0.01, 0.25, 0.3, 0.2, 0.1)
    q = arm.home_q + 0.1
    jac = arm.jacobian(q, tool)
    h = 1e-7
    t0 = arm.fk(q, tool)
    for i in range(arm.n_joints):
        dq = np.zeros(arm.n_joints)
        dq[i] = h
        t1 = arm.fk(q + dq, tool)
        np.testing.assert_allclose((t1[:3, 3] - t0[:3, 3]) / h, jac[:3, i], atol=1e-5, err_msg="linear rows")
        w = (t1[:3, :3] @ t0[:3, :3].T - np.eye(3)) / h
        np.testing.assert_allclose([w[2, 1], w[0, 2], w[1, 0]], jac[3:, i], atol=1e-5, err_msg="angular rows")


def test_inverse_dynamics_agrees_with_mujoco(arm) -> None:
    mujoco = pytest.importorskip("mujoco")
    m = mujoco.MjModel.from_xml_path(str(arm.mjcf_path))
    d = mujoco.MjData(m)
    rng = np.random.default_rng(7)
    for _ in range(5):
        q = rng.uniform(arm.q_min, arm.q_max)
        qd, qdd = rng.uniform(-2, 2, arm.n_joints), rng.uniform(-5, 5, arm.n_joints)
        d.qpos[:], d.qvel[:], d.qacc[:] = q, qd, qdd
        mujoco.mj_inverse(m, d)
        np.testing.assert_allclose(arm.inverse_dynamics(q, qd, qdd), d.qfrc_inverse, atol=1e-8,
                                   err_msg="controller model and plant must be one model (no damping)")


def test_mass_matrix_is_symmetric_and_gravity_is_rnea_at_rest(arm) -> None:
    q = arm.home_q + 0.2
    mm = arm.mass_matrix(q)
    np.testing.assert_array_equal(mm, mm.T)
    assert np.all(np.linalg.eigvalsh(mm) > 0)
    zero = np.zeros(arm.n_joints)
    np.testing.assert_allclose(arm.gravity(q), arm.inverse_dynamics(q, zero, zero), atol=1e-9)


def test_payload_adds_its_weight_at_the_flange() -> None:
    arm = load_robot("irb2400")
    q = arm.home_q
    zero = np.zeros(6)
    extra = arm.inverse_dynamics(q, zero, zero, payload_kg=10.0) - arm.inverse_dynamics(q, zero, zero)
    # A 10 kg point at the flange: torque on j2 = r x F, about -(x_flange - x_j2) * m g.
    lever_m = arm.fk(q)[0, 3] - 0.100
    assert extra[1] == pytest.approx(-lever_m * 10.0 * 9.81, rel=1e-9)
    np.testing.assert_allclose(arm.inverse_dynamics(q, zero, zero), arm.gravity(q), atol=1e-9)


def test_joint_limit_names_the_joint_in_degrees() -> None:
    arm = load_robot("irb2400")
    q = arm.home_q.copy()
    q[2] = math.radians(70)
    with pytest.raises(JointLimit, match=r"joint 3 of irb2400 at 70\.000 deg .* -60\.0\.\.65\.0 deg"):
        arm.check_limits(q)
    arm.check_limits(arm.home_q)


@pytest.mark.parametrize(
    "call",
    [
        pytest.param(lambda a: a.fk([0, 0, math.nan, 0, 0, 0]), id="fk-nan"),
        pytest.param(lambda a: a.jacobian([0, 0, 0, math.inf, 0, 0]), id="jacobian-inf"),
        pytest.param(lambda a: a.inverse_dynamics(np.zeros(6), np.zeros(6), [math.nan] * 6), id="rnea-nan"),
        pytest.param(lambda a: a.fk(np.zeros(5)), id="wrong-length"),
        pytest.param(lambda a: a.fk(np.zeros(6), tool=np.full((4, 4), math.nan)), id="tool-nan"),
        pytest.param(lambda a: a.inverse_dynamics(np.zeros(6), np.zeros(6), np.zeros(6), payload_kg=-1), id="neg-payload"),
    ],
)
def test_bad_numbers_raise_the_projects_usage_error(call) -> None:
    with pytest.raises(UsageError):
        call(load_robot("irb2400"))


def test_the_batched_rnea_gives_the_numbers_of_the_single_calls_and_follows_payload_changes() -> None:
    arm = load_robot("irb2400")
    rng = np.random.default_rng(4)
    q, qd, qdd = (rng.normal(0.0, 1.0, (5, arm.n_joints)) for _ in range(3))
    single, rows = arm.inverse_dynamics_function(), arm.inverse_dynamics_rows_function()
    for payload_kg in (0.0, 12.0, 3.0):
        arm.set_payload(payload_kg)
        out = np.zeros(q.shape)
        rows(q, qd, qdd, out)
        assert np.array_equal(out, np.array([single(a, b, c) for a, b, c in zip(q, qd, qdd)])), payload_kg


def test_the_rigid_body_rows_are_made_once_per_payload_and_follow_its_changes() -> None:
    arm = load_robot("irb2400")
    first = arm.rigid_body_rows()
    assert first is not None and arm.rigid_body_rows() is first   # the same payload: the rows made once
    arm.set_payload(12.0, (0.0, 0.0, 0.1))
    loaded = arm.rigid_body_rows()
    assert loaded is not first and loaded[-1, 15] == first[-1, 15] + 12.0   # the payload's mass on the last link
    arm.set_payload(12.0, (0.0, 0.0, 0.1))   # the same payload again: nothing to make
    assert arm.rigid_body_rows() is loaded
    arm.set_payload(0.0)
    assert np.array_equal(arm.rigid_body_rows(), first)
