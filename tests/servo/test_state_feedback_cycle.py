"""The elastic gears' motion cycle as one kernel runs the steps the Python loop it was written from runs."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

from orc_rpl.motion import CartesianMotion, JointMotion, Params, make_virtual_motion_layer
from orc_rpl.plant import compiled, realistic
from orc_rpl.world.pose import Pose

pytestmark = [pytest.mark.sim,
              pytest.mark.skipif(not compiled.AVAILABLE,
                                 reason="the kernels are off (numba not installed, or ORC_RPL_NO_JIT=1)")]

#: A thermal period of whole motion cycles (4 steps): the kernel steps the thermal model at a call's end, the Python
#: loop at the step it falls on; with 48 both at the same step (with 50, every 0.05 s the plant's friction changes
#: two steps apart, and the runs part at the encoders' rounding from there).
WHOLE_CYCLES_STEPS = 48


@pytest.fixture(autouse=True)
def _kernels_back_on() -> Iterator[None]:
    before = compiled.use_kernels(True)
    yield
    compiled.use_kernels(before)


def _recorded_run(kernel: bool, monkeypatch: pytest.MonkeyPatch) -> tuple[np.ndarray, int]:
    """Every motion cycle of a short program on the elastic plant (undeclared payload, a zone, a declared load, a
    line): the plant's and the measured state, the servo's signals, the filter's state and the copper sums."""
    monkeypatch.setattr(realistic, "THERMAL_EVERY_STEPS", WHOLE_CYCLES_STEPS)
    monkeypatch.setattr(realistic.RealisticCell._heat, "__defaults__", (WHOLE_CYCLES_STEPS,))
    layer = make_virtual_motion_layer("irb2400", backend="servo", plant="realistic", seed=3, elastic=True,
                                      gear_feedforward=True, state_feedback=True)
    loop = layer.backend.loop
    loop.set_payload(5.0, known=False)
    in_kernel = [0]
    if kernel:
        run = loop._state_feedback_cycle.run

        def counted(*args: Any) -> np.ndarray:
            in_kernel[0] += 1
            return run(*args)

        loop._state_feedback_cycle.run = counted
    else:
        loop.use_compiled_law(False)   # the Python loop, the reference
    home = np.array(layer.kin.arm.home_q)
    p = Pose.from_matrix(layer.fk(home))
    rows = []
    for motion, params in [(JointMotion(tuple(home + np.array([0.6, 0.3, -0.2, 0.4, -0.3, 0.8]))), Params(zone_m=0.05)),
                           (JointMotion(tuple(home)), Params(load_kg=4.0)),
                           (CartesianMotion(Pose(p.x, p.y + 0.2, p.z - 0.15, p.a, p.b, p.c)), Params())]:
        h = layer.move(motion, params)
        while not h.done:
            layer.tick()
            cell, servo, law = loop.cell, loop.servo, loop.state_feedback
            rows.append(np.concatenate([cell.true_q, cell.link_q, cell.true_qd, cell.q, cell.qd, servo.integral,
                                        servo.position_error, servo.velocity_error, servo.torque, servo.torque_ff,
                                        servo.saturated, law.state, law.twist_rad, cell._tau_sq_sum,
                                        law.k.ravel(), law.l.ravel(), [law.scheduled, law.kept]]))
    return np.array(rows), in_kernel[0]


def test_the_compiled_cycle_runs_the_python_loops_steps(monkeypatch: pytest.MonkeyPatch) -> None:
    compiled_run, in_kernel = _recorded_run(True, monkeypatch)
    reference, _ = _recorded_run(False, monkeypatch)
    assert compiled_run.shape == reference.shape and len(reference) > 500
    assert in_kernel == len(reference)   # every motion cycle was the kernel
    difference = np.abs(compiled_run - reference) / np.maximum(1.0, np.abs(reference))
    # rounding (the compiled RNEA, M_ii and tanh) until the encoders' rounding first turns it into a count ...
    assert np.max(difference[:25]) < 1e-9, np.max(difference[:25])
    # ... and from there the closed loop keeps the runs together: motors and links within 1e-6 rad all along
    angles = slice(0, 12)
    assert np.max(np.abs(compiled_run[:, angles] - reference[:, angles])) < 1e-6
    # the schedule inside the kernel made the gains again, and kept them, on the Python schedule's cycles
    np.testing.assert_array_equal(compiled_run[:, -2:], reference[:, -2:])
    gains = slice(-2 - (3 * 12 + 15 * 6), -2)   # k (m x 4m) and l (5m x 2m) of the three slow joints
    # and the gains it made are the Python schedule's: to the rounding at first, then within what the encoders' counts
    # move the pose (measured 2.3e-7 of the largest gain)
    assert np.max(np.abs(compiled_run[:25, gains] - reference[:25, gains])) <= 1e-9 * np.max(np.abs(reference[:25, gains]))
    assert np.max(np.abs(compiled_run[:, gains] - reference[:, gains])) <= 1e-5 * np.max(np.abs(reference[:, gains]))
    assert compiled_run[-1, -2] > 50 and compiled_run[-1, -1] > 50


def test_the_state_the_kernel_returns_is_what_the_loop_measures_after_it() -> None:
    layer = make_virtual_motion_layer("irb2400", backend="servo", plant="realistic", seed=5, elastic=True,
                                      gear_feedforward=True, state_feedback=True)
    loop, backend = layer.backend.loop, layer.backend
    home = np.array(layer.kin.arm.home_q)
    h = layer.move(JointMotion(tuple(home + np.array([0.5, 0.2, -0.2, 0.3, -0.2, 0.6]))), Params())
    cycles = 0
    while not h.done:
        layer.tick()
        returned, measured = backend._state, loop.state()
        assert returned.time_s == measured.time_s
        for name in ("q", "qd", "tau", "position_error"):
            assert np.array_equal(getattr(returned, name), getattr(measured, name)), name
        cycles += 1
    assert cycles > 100 and loop.state_feedback.scheduled > 0
