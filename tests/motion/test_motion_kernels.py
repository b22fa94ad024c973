"""The motion room's compiled per-cycle kernels compute what the numpy (Python) code they were written from computes."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

from orc_rpl.motion import JointMotion, Params, make_virtual_motion_layer
from orc_rpl.motion.paths import DensePath
from orc_rpl.motion.trajectory import SplinePath
from orc_rpl.plant import compiled

pytestmark = [pytest.mark.sim, pytest.mark.skipif(not compiled.AVAILABLE, reason="no kernels to compare: numba is not installed or ORC_RPL_NO_JIT=1")]


@pytest.fixture(autouse=True)
def _setting_kept() -> Iterator[None]:
    """The tests switch the kernels on and off (each says which it starts with); the process' setting comes back."""
    setting = compiled.ON
    yield
    compiled.use_kernels(setting)


def test_the_compiled_winding_sample_calibrates_and_corrects_as_the_python_code_over_a_run() -> None:
    compiled.use_kernels(True)
    layer = make_virtual_motion_layer("irb2400", plant="realistic", seed=4)
    layer.backend.loop.set_payload(10.0, known=False)
    winding = layer.winding
    sample = winding._sample
    worst, compared, corrected = [0.0], [0], [0]

    def both(*measured: Any) -> None:
        # the same sample twice from the same state: Python first (the reference), then the kernel, which goes on
        saved = (winding.rise_k.copy(), winding._sums.copy(), winding._flags.copy(), winding._calibrating,
                 winding._samples)
        compiled.use_kernels(False)
        sample(*measured)
        reference = (winding.rise_k.copy(), winding._sums.copy(), winding._flags.copy(), winding._calibrating)
        winding.rise_k[:], winding._sums[:], winding._flags[:] = saved[0], saved[1], saved[2]
        winding._calibrating, winding._samples = saved[3], saved[4]
        compiled.use_kernels(True)
        sample(*measured)
        assert np.array_equal(winding._flags, reference[2]) and winding._calibrating == reference[3]
        for got, want in zip((winding.rise_k, winding._sums), reference[:2]):
            worst[0] = max(worst[0], float(np.max(np.abs(got - want) / np.maximum(np.abs(want), 1.0))))
        compared[0] += 1
        corrected[0] += not np.array_equal(saved[0], winding.rise_k)

    winding._sample = both  # type: ignore[method-assign]
    for target in ((0, -30, -40, 0, 30, 0), (150, 70, -20, 0, -60, 90), (-100, -40, 10, 90, 40, 0)):
        layer.wait(layer.move(JointMotion(tuple(np.radians(target))), Params(load_kg=10.0)))
    assert compared[0] > 100 and corrected[0] > 5, (compared, corrected)
    assert np.all(winding._flags[0, :3]), "the large motors calibrate during the run"
    assert worst[0] <= 1e-10, worst


@pytest.mark.parametrize("points", [2, 3, 40])
def test_the_compiled_spline_gives_scipys_values_and_derivatives_on_and_between_the_knots_and_beyond(points: int) -> None:
    compiled.use_kernels(True)
    rng = np.random.default_rng(points)
    q = np.cumsum(rng.normal(size=(points, 6)), axis=0)
    path = SplinePath(DensePath(q, q[:, :3], np.ones(points, dtype=int), np.linspace(0.0, 1.0, points)))
    x = np.concatenate([path.x_knots, rng.uniform(-0.3, path.length + 0.3, 300), [0.0, path.length]])
    compiled_orders = path.orders(x)
    for order, got in enumerate(compiled_orders):
        want = path.spline(x, order)
        assert got.shape == want.shape
        assert float(np.max(np.abs(got - want))) <= 1e-10 * max(1.0, float(np.max(np.abs(want))))


def _estimates() -> tuple[Any, Any, Any]:
    """The realistic irb2400's three per-cycle estimates, as the virtual robot makes them (no drive measurement)."""
    from orc_rpl.motion.gear_friction import GearFriction
    from orc_rpl.motion.thermal import ThermalModel, WindingTemperature
    from orc_rpl.robot import load_robot
    from orc_rpl.robot.plants import COPPER_TEMPCO_1_K, plant_spec

    n = plant_spec("irb2400")
    thermal = ThermalModel.for_arm(load_robot("irb2400").tau_max, 0.004)
    winding = WindingTemperature(n.torque_per_amp_nm_a, n.winding_resistance_ohm, n.winding_rth_k_w,
                                 n.winding_time_constant_s, n.ambient_c, 0.004, COPPER_TEMPCO_1_K)
    gear = GearFriction(n.coulomb_nm, n.viscous_nm_s, n.gear_rth_k_w, n.gear_time_constant_s, n.cold_friction_factor,
                        n.warm_rise_k, n.gear_motor_heat_share, n.torque_per_amp_nm_a, n.winding_resistance_ohm,
                        COPPER_TEMPCO_1_K, n.ambient_c, 0.004)
    return thermal, winding, gear


def _fused_against_own_updates(fused: tuple[Any, Any, Any], reference: tuple[Any, Any, Any], cycles: int,
                               seed: int) -> None:
    """`cycles` random motion cycles of the fused update (kernels on) and of each one's own (numpy): the same."""
    from orc_rpl.motion.gear_friction import update_estimates

    rng = np.random.default_rng(seed)
    for _ in range(cycles):
        tau, qd = rng.normal(0.0, 200.0, 6), rng.normal(0.0, 1.5, 6)
        compiled.use_kernels(True)
        update_estimates(*fused, tau, qd)
        compiled.use_kernels(False)
        update_estimates(*reference, tau, qd)
    for got, want in zip((fused[0].load, fused[1].rise_k, fused[2].rise_k),
                         (reference[0].load, reference[1].rise_k, reference[2].rise_k)):
        assert np.all(want > 0.0)
        assert float(np.max(np.abs(got - want) / want)) <= 1e-10


def test_the_fused_update_of_the_three_estimates_gives_each_ones_own_update() -> None:
    _fused_against_own_updates(_estimates(), _estimates(), 300, 5)   # 12 gearbox integrations


def test_after_a_reset_the_fused_update_still_updates_each_estimates_own_arrays() -> None:
    fused, reference = _estimates(), _estimates()
    for estimates in (fused, reference):
        for estimate in estimates:
            estimate.reset()   # a cold start: what each one hands the fused update must still be what it reports
        estimates[2].warm_up(10.0)
    _fused_against_own_updates(fused, reference, 60, 6)


def test_the_path_velocity_controllers_compiled_range_from_the_rows_parts_is_the_numpy_range() -> None:
    from orc_rpl.arm.pvc import PathVelocityController

    layer = make_virtual_motion_layer("irb2400", plant="realistic")
    backend, servo = layer.backend, layer.backend.loop.servo
    rng = np.random.default_rng(3)
    x_f = np.linspace(0.0, 1.0, 4 * 150 + 1)
    sd_f = np.full(len(x_f), 0.8)
    targets = rng.normal(0.0, 0.6, (2, 6))
    path = lambda x, order: (targets[0] + np.multiply.outer(x, targets[1]) if order == 0
                             else np.broadcast_to(targets[1] if order == 1 else 0.0 * targets[1], np.shape(x) + (6,)).copy())
    pvc = PathVelocityController(path, x_f, sd_f, 4, 0.001, backend.path_dynamics, layer.kin.arm.tau_max,
                                 dynamics_rows=backend.path_dynamics_rows)
    assert pvc._parts is not None
    for cycle in (0, 1, 40, 99, 100, 150):
        servo.integral = rng.normal(0.0, 30.0, 6)
        compiled.use_kernels(False)
        want = pvc.admissible(0.0, 0.0, cycle)
        compiled.use_kernels(True)
        assert pvc.admissible(0.0, 0.0, cycle) == want, cycle
