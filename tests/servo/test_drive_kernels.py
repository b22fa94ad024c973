"""The compiled per-cycle kernels (numba) compute what the numpy code they were written from computes."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
import pytest

from orc_rpl.errors import UsageError
from orc_rpl.motion import CartesianMotion, JointMotion, Params, make_virtual_motion_layer
from orc_rpl.plant import compiled
from orc_rpl.robot.model import load_robot
from orc_rpl.world.pose import Pose

pytestmark = [pytest.mark.sim, pytest.mark.skipif(not compiled.AVAILABLE, reason="the kernels are off (numba not installed, or ORC_RPL_NO_JIT=1)")]


@pytest.fixture(autouse=True)
def _kernels_back_on() -> Iterator[None]:
    before = compiled.use_kernels(True)
    yield
    compiled.use_kernels(before)


def _recorded_run(kernels: bool, friction: bool, compiled_rnea: bool) -> np.ndarray:
    rows, cycles_in_kernel = _run(kernels, friction, compiled_rnea)
    # the drives' whole motion cycle ran as the kernel (or never, for the reference)
    assert (cycles_in_kernel == len(rows)) if kernels else cycles_in_kernel == 0
    return rows


def _run(kernels: bool, friction: bool, compiled_rnea: bool) -> tuple[np.ndarray, int]:
    """Every motion cycle of a short mixed program on the realistic plant (undeclared payload): the plant's
    state, what the servo measured, its integral, error and torque, the copper sums and the estimates."""
    compiled.use_kernels(kernels)
    layer = make_virtual_motion_layer("irb2400", backend="servo", plant="realistic", seed=5)
    loop = layer.backend.loop
    loop.drives.compiled_rnea = compiled_rnea
    loop.cell.compiled_heat = compiled_rnea   # exp and pow: the C library's (compiled) or numpy's, bit for bit
    cycles_in_kernel = [0]
    run_kernel = loop.cell.drives.run_kernel

    def counted(*args: object) -> None:
        cycles_in_kernel[0] += 1
        run_kernel(*args)

    loop.cell.drives.run_kernel = counted  # type: ignore[method-assign]
    loop.set_payload(6.0, known=False)
    if not friction:
        loop.servo.set_friction(None)
    home = np.array(layer.kin.arm.home_q)
    p = Pose.from_matrix(layer.fk(home))
    moves = [(JointMotion(tuple(home + np.array([0.8, 0.3, -0.2, 0.5, -0.3, 1.0]))), Params(zone_m=0.05)),
             (JointMotion(tuple(home)), Params(load_kg=4.0)),
             (CartesianMotion(Pose(p.x, p.y + 0.3, p.z - 0.2, p.a, p.b, p.c)), Params())]
    rows = []
    for motion, params in moves:
        h = layer.move(motion, params)
        while not h.done:
            layer.tick()
            cell, servo, pipe = loop.cell, loop.servo, layer
            rows.append(np.concatenate([cell.true_q, cell.true_qd, cell.q, cell.qd, servo.integral,
                                        servo.position_error, servo.torque, cell._tau_sq_sum, cell.winding_rise_k,
                                        pipe.thermal.load, pipe.winding.rise_k, pipe.gear_friction._speed_sum]))
    return np.array(rows), cycles_in_kernel[0]


def test_the_compiled_motion_cycle_is_the_numpy_cycle_bit_for_bit() -> None:
    # without the friction feed-forward's tanh (numpy's and the C library's differ in the last bit), with
    # Pinocchio's RNEA and numpy's exp and pow in the plant's thermal model, the kernels do the numpy
    # code's operations in its order: the same bits
    compiled_run = _recorded_run(True, friction=False, compiled_rnea=False)
    reference = _recorded_run(False, friction=False, compiled_rnea=False)
    assert compiled_run.shape == reference.shape and len(reference) > 300
    assert np.array_equal(compiled_run, reference)


def test_the_whole_compiled_stack_stays_within_rounding_of_the_reference() -> None:
    # everything on (tanh from the C library, the compiled RNEA and mass matrix): rounding, never drift
    compiled_run = _recorded_run(True, friction=True, compiled_rnea=True)
    reference = _recorded_run(False, friction=True, compiled_rnea=False)
    assert compiled_run.shape == reference.shape
    worst = np.max(np.abs(compiled_run - reference) / np.maximum(1.0, np.abs(reference)))
    assert worst < 1e-10, worst


@pytest.mark.parametrize("robot", ["irb2400", "ur5e"])
@pytest.mark.parametrize("payload_kg", [0.0, 12.0])
def test_the_compiled_rnea_and_mass_diagonal_match_pinocchio(robot: str, payload_kg: float) -> None:
    from orc_rpl.servo.rnea_kernel import mass_diagonal, mass_matrix_block, rnea_row

    arm = load_robot(robot)
    arm.set_payload(payload_kg, (0.01, 0.02, 0.05))
    body = arm.rigid_body_rows()
    assert body is not None
    rng = np.random.default_rng(1)
    q, qd, qdd = (rng.standard_normal((40, arm.n_joints)) * scale for scale in (2.0, 2.0, 5.0))
    tau, work = np.empty(q.shape), np.zeros((arm.n_joints, 15))
    for row in range(len(q)):
        rnea_row(body, arm.gravity_m_s2, q[row], qd[row], qdd[row], tau[row], work)
    reference = np.array([arm.inverse_dynamics_unchecked(*row) for row in zip(q, qd, qdd)])
    assert np.max(np.abs(tau - reference) / np.maximum(1.0, np.abs(reference))) < 1e-12
    for row in q:
        diagonal = np.empty(arm.n_joints)
        mass_diagonal(body, row, diagonal)
        expected = arm.mass_matrix_diagonal_unchecked(row)
        assert np.max(np.abs(diagonal - expected) / expected) < 1e-12
        joints = np.array([0, 1, 2])   # the state feedback's block of the whole matrix, symmetric to the bit
        block = np.empty((3, 3))
        mass_matrix_block(body, row, joints, block)
        full = arm.mass_matrix(row, payload_kg, (0.01, 0.02, 0.05))[:3, :3]
        assert np.max(np.abs(block - full)) < 1e-12 * np.max(np.abs(full)) and np.array_equal(block, block.T)


def test_the_path_velocity_controllers_range_is_the_numpy_range() -> None:
    from orc_rpl.arm.pvc import PathVelocityController

    rng = np.random.default_rng(4)
    pvc = PathVelocityController.__new__(PathVelocityController)   # only admissible()'s arithmetic is used
    for trial in range(200):
        b1, b2 = rng.standard_normal(6) * 50.0, rng.standard_normal(6) * 300.0
        if trial % 3 == 0:
            b1[rng.integers(6)] = 0.0   # a joint the path acceleration does not move
        limit = np.abs(rng.standard_normal(6)) * 400.0 + 10.0
        pvc.limit, pvc._minus_limit, pvc._at_cycle = limit, -limit, lambda _: (b1, b2)
        from orc_rpl.arm import pvc_kernels

        pvc._range = pvc_kernels.admissible_range
        compiled.use_kernels(True)
        fast = pvc.admissible(0.0, 0.0, 0)
        compiled.use_kernels(False)
        assert fast == pvc.admissible(0.0, 0.0, 0)


def test_a_reference_that_is_not_finite_is_refused_with_the_kernels_too() -> None:
    layer = make_virtual_motion_layer("irb2400", backend="servo", plant="realistic")
    loop, q = layer.backend.loop, np.array(layer.kin.arm.home_q)
    bad = q.copy()
    bad[2] = np.nan
    rows = np.tile(q, (4, 1))
    rows[3, 1] = np.inf
    zero = np.zeros(6)
    with pytest.raises(UsageError, match="NaN or infinity"):
        loop.run(bad, zero, zero, 4)
    with pytest.raises(UsageError, match="NaN or infinity"):
        loop.run(rows, np.zeros((4, 6)), np.zeros((4, 6)), 4)
    state = loop.run(q, zero, zero, 4)   # and a good one runs
    assert np.allclose(state.q, q, atol=1e-3)


def test_the_plants_compiled_winding_measurement_and_heating_are_numpys() -> None:
    from orc_rpl.plant.realistic import RealisticCell

    results = {}
    for on in (True, False):
        compiled.use_kernels(on)
        cell = RealisticCell("irb2400", seed=2)
        cell.reset()
        samples = []
        for k in range(700):
            cell.step(np.array([100.0, 300.0, -200.0, 20.0, 10.0, 5.0]) * np.sin(k / 50.0))
            if k == 400:
                cell.set_brakes(True)
            if k % 25 == 0:
                samples.append(np.concatenate(cell.winding_measurement()))
        state = np.concatenate([cell.winding_rise_k, cell.gear_rise_k, cell._coulomb_now, cell._viscous_now,
                                cell._model.dof_damping, cell._model.dof_frictionloss, cell.true_q])
        results[on] = np.array(samples), state
    assert np.array_equal(results[True][0][:2], results[False][0][:2])   # before the first heating (step 50): bit for bit
    samples_c, state_c = results[True]
    samples_n, state_n = results[False]
    assert np.max(np.abs(samples_c - samples_n) / np.maximum(1.0, np.abs(samples_n))) < 1e-12
    assert np.max(np.abs(state_c - state_n) / np.maximum(1.0, np.abs(state_n))) < 1e-12


def test_numba_is_imported_by_a_simulation_not_by_importing_the_package() -> None:
    import subprocess
    import sys

    code = ("import sys, orc_rpl.cli, orc_rpl.motion, orc_rpl.arm.pvc, orc_rpl.servo.loop, orc_rpl.plant.realistic\n"
            "print('numba' in sys.modules)\n"
            "from orc_rpl.motion import make_virtual_motion_layer\n"
            "make_virtual_motion_layer('irb2400', plant='realistic')\n"
            "print('numba' in sys.modules)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert out == ["False", "True"]
