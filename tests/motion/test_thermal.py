"""The thermal load estimate (thesis 2.4, 4.5): first-order low-pass of (tau / tau_continuous)^2, 1 = the motor's limit."""

from __future__ import annotations

import math

import numpy as np
import pytest

from orc_rpl.errors import UsageError
from orc_rpl.motion import MotionLayer, make_virtual_motion_layer
from orc_rpl.motion.thermal import CONTINUOUS_SHARE, TIME_CONSTANTS_S, ThermalModel


def test_a_constant_torque_heats_and_rest_cools_as_the_closed_form() -> None:
    model = ThermalModel([100.0, 50.0], [20.0, 10.0], 0.004)
    tau = np.array([80.0, 75.0])                   # u = 0.64 and 2.25 (an overload)
    u = (tau / model.tau_continuous_nm) ** 2
    for _ in range(2500):                          # 10 s
        model.update(tau)
    expected = u * (1.0 - np.exp(-10.0 / model.time_constants_s))
    assert np.allclose(model.load, expected, rtol=1e-12, atol=0.0), "exact discretisation of dx/dt = (u - x) / T"
    start = model.load.copy()
    for _ in range(5000):                          # 20 s at rest
        model.update(np.zeros(2))
    assert np.allclose(model.load, start * np.exp(-20.0 / model.time_constants_s), rtol=1e-12, atol=0.0)


def test_the_estimate_is_one_at_the_continuous_torque_in_steady_state() -> None:
    model = ThermalModel.for_arm([1800.0], 0.004)
    for _ in range(int(10 * TIME_CONSTANTS_S[0] / 0.004)):
        model.update(np.array([CONTINUOUS_SHARE * 1800.0]))
    assert model.load[0] == pytest.approx(1.0, abs=1e-4)


@pytest.mark.parametrize("tau_c, t, period", [([0.0], [1.0], 0.004), ([1.0], [-1.0], 0.004), ([1.0], [1.0], 0.0),
                                              ([1.0, 2.0], [1.0], 0.004)])
def test_bad_constants_are_refused(tau_c: list[float], t: list[float], period: float) -> None:
    with pytest.raises(UsageError):
        ThermalModel(tau_c, t, period)


@pytest.mark.sim
def test_on_the_simulated_cell_a_held_torque_heats_and_the_decay_has_the_documented_time_constant(servo: MotionLayer) -> None:
    servo.run_for(1.0)  # settle at home: the servo holds the arm against gravity, a sustained torque
    thermal = servo.thermal
    assert thermal is not None
    tau = np.array(servo.backend.torque())
    u = (tau / thermal.tau_continuous_nm) ** 2
    assert u[1] > 0.01, "motor 2 carries the arm's weight at home"
    heated = servo.thermal_load()
    # from cold, 1 s of (nearly) that torque: x = u (1 - e^(-t/T)) within the settling transient
    assert np.allclose(heated[:3], u[:3] * (1.0 - np.exp(-1.0 / thermal.time_constants_s[:3])), rtol=0.05)
    thermal.load[:] = 1.0                          # a hot motor, then 5 s more at rest
    servo.run_for(5.0)
    u = (np.array(servo.backend.torque()) / thermal.tau_continuous_nm) ** 2
    x = servo.thermal_load()
    expected = u + (1.0 - u) * np.exp(-5.0 / thermal.time_constants_s)
    assert np.allclose(x, expected, rtol=1e-3), "x(t) = u + (x0 - u) e^(-t/T) while the torque holds"
    identified = -5.0 / np.log((x[1] - u[1]) / (1.0 - u[1]))
    print(f"\nmotor 2: u = {u[1]:.4f}, x(5 s) = {x[1]:.4f}, identified T = {identified:.3f} s "
          f"(documented {TIME_CONSTANTS_S[1]} s)")
    assert identified == pytest.approx(TIME_CONSTANTS_S[1], rel=1e-2)


def test_the_kinematic_robot_estimates_from_its_model_torques(kinematic: MotionLayer) -> None:
    kinematic.run_for(0.4)
    assert kinematic.thermal_load()[1] > 0.0, "gravity on motor 2 heats it even on the kinematic robot"
    assert math.isfinite(float(kinematic.thermal_load().sum()))


def test_every_motion_layer_has_the_estimate() -> None:
    layer = make_virtual_motion_layer(robot="ur5e", backend="kinematic")
    assert layer.thermal_load().shape == (6,)
