"""The path velocity controller: the path is kept, time stretches under torque limits, the nominal is kept when feasible."""

from __future__ import annotations

import numpy as np
import pytest

from orc_rpl.arm.pvc import PathVelocityController
from orc_rpl.motion import JointMotion, Params, make_virtual_motion_layer

H, SUB = 0.001, 4
DIRECTION = np.array([1.0, 0.5])


def line(x: object, order: int) -> np.ndarray:
    """A straight joint path q = x * DIRECTION."""
    x = np.asarray(x, dtype=float)
    if order == 0:
        return x[..., None] * DIRECTION if x.ndim else x * DIRECTION
    shape = (*x.shape, 2) if x.ndim else (2,)
    return np.broadcast_to(DIRECTION if order == 1 else np.zeros(2), shape).copy()


def trapezoid(accel: float, length: float) -> tuple[np.ndarray, np.ndarray]:
    """x(t), x'(t) per servo step: accelerate, then brake, at `accel` (rad/s^2 of x)."""
    t_half = np.sqrt(length / accel)
    steps = int(np.ceil(2 * t_half / H / SUB)) * SUB
    t = np.minimum(np.arange(steps + 1) * H, 2 * t_half)
    up = t <= t_half
    x = np.where(up, 0.5 * accel * t**2, length - 0.5 * accel * (2 * t_half - t) ** 2)
    sd = np.where(up, accel * t, accel * (2 * t_half - t))
    return x, sd


def inertia_only(q: np.ndarray, d1: np.ndarray, d2: np.ndarray, sd: float) -> tuple[np.ndarray, np.ndarray]:
    return 2.0 * d1, np.zeros(2)  # tau = 2 q'' on each joint


def run(controller: PathVelocityController) -> tuple[list[object], np.ndarray]:
    outputs, commanded = [], []
    k = 0
    while not controller.done and k < 10_000:
        k += 1
        rows = controller.cycle(k)
        outputs.append(rows)
        if rows is not None:
            commanded.extend(rows[0])
    return outputs, np.array(commanded)


def test_when_the_torques_suffice_the_nominal_rows_are_used_unchanged() -> None:
    x, sd = trapezoid(4.0, 1.0)
    controller = PathVelocityController(line, x, sd, SUB, H, inertia_only, np.array([100.0, 100.0]))
    outputs, _ = run(controller)
    assert all(rows is None for rows in outputs) and len(outputs) == (len(x) - 1) // SUB
    assert controller.lag_s() == 0.0 and controller.scaled_cycles == 0


def test_under_a_torque_limit_time_stretches_and_the_path_is_kept() -> None:
    x, sd = trapezoid(4.0, 1.0)
    # tau = 2 * 4 = 8 N m on joint 1 for the nominal; allow 5 (x 0.95): about 2.4 rad/s^2
    controller = PathVelocityController(line, x, sd, SUB, H, inertia_only, np.array([5.0, 5.0]))
    outputs, commanded = run(controller)
    assert controller.done and controller.scaled_cycles > 0
    assert len(outputs) > 1.2 * (len(x) - 1) / SUB, "slower than nominal"
    # every commanded reference lies on the path, and the path is followed forward to its end
    s = commanded[:, 0]
    assert np.allclose(commanded[:, 1], 0.5 * s, atol=1e-12)
    assert np.all(np.diff(s) >= -1e-12) and s[-1] == pytest.approx(1.0, abs=1e-12)


def test_a_late_command_slows_down_once_at_the_end_never_stalls_and_starts_again() -> None:
    x, sd = trapezoid(4.0, 1.0)

    def against_a_load(q: np.ndarray, d1: np.ndarray, d2: np.ndarray, sd: float) -> tuple[np.ndarray, np.ndarray]:
        return 2.0 * d1, np.full(2, 3.0)  # tau = 2 q'' + 3: the load slows the acceleration, helps the braking

    # 9 N m: the command accelerates at 3 where the nominal does at 4 and is late when the nominal brakes
    controller = PathVelocityController(line, x, sd, SUB, H, against_a_load, np.array([9.0, 9.0]) / 0.95)
    _, commanded = run(controller)
    speed = np.diff(commanded[:, 0]) / H
    top = int(np.argmax(speed))
    assert np.all(np.diff(speed[top:]) <= 1e-9), "from its top speed on, the command only slows down"
    assert commanded[-1, 0] == pytest.approx(1.0, abs=1e-12)


@pytest.mark.sim
def test_an_undeclared_payload_on_a_cold_plant_keeps_the_path_with_the_controller() -> None:
    errors, saturated = {}, {}
    for pvc in (False, True):
        layer = make_virtual_motion_layer(plant="realistic", seed=2)
        loop = layer.backend.loop
        loop.set_payload(15.0, known=False)
        counts = [0, 0]

        def count() -> None:
            counts[0] += bool(loop.servo.saturated.any())
            counts[1] += 1

        loop.on_step.append(count)
        h = layer.move(JointMotion(tuple(np.radians((0, -30, -40, 0, 30, 0)))), Params(load_kg=10.0, path_velocity=pvc))
        worst, reference_end = 0.0, None
        while not h.done:
            layer.tick()
            worst = max(worst, float(np.max(np.abs(loop.servo.position_error))))
            if reference_end is None and layer.idle() or layer._settling is not None:
                reference_end = reference_end or layer.now_s()
        errors[pvc], saturated[pvc] = worst, counts[0] / counts[1]
        assert h.t_end_s == pytest.approx(reference_end, abs=0.0041), "T_d is when the reference really ends"
    assert errors[True] < errors[False] / 5, errors
    assert saturated[True] < saturated[False] / 10, saturated


@pytest.mark.sim
def test_a_stop_while_time_is_scaled_brakes_from_where_the_command_is() -> None:
    layer = make_virtual_motion_layer(plant="realistic", seed=2)
    layer.backend.loop.set_payload(15.0, known=False)
    h = layer.move(JointMotion(tuple(np.radians((0, -30, -40, 0, 30, 0)))), Params(load_kg=10.0))
    while layer.pvc is not None and layer.pvc.in_sync:
        layer.tick()
    assert layer.pvc is not None and not layer.pvc.in_sync, "the undeclared payload made the controller slow down"
    before = layer.reference_q()
    layer.stop_move()
    layer.tick()
    step = np.max(np.abs(layer.reference_q() - before))
    assert step < 0.01, "the brake continues from the commanded state, no jump"
    layer.run_until_idle()
    assert h.status.value == "act_stopped" and np.max(np.abs(layer.backend.qd())) < 0.05
