"""The path velocity controller's check from model torques computed in blocks: the numbers of the point-wise call."""

from __future__ import annotations

import numpy as np
import pytest

from orc_rpl.motion import make_virtual_motion_layer
from orc_rpl.motion.virtual import ROWS_BLOCK

pytestmark = pytest.mark.sim


def test_path_dynamics_rows_equal_the_point_wise_call_also_after_a_payload_change() -> None:
    layer = make_virtual_motion_layer("irb2400", plant="realistic")
    backend, servo = layer.backend, layer.backend.loop.servo
    rng = np.random.default_rng(2)
    n_rows = ROWS_BLOCK + 30   # two blocks
    q, d1, d2 = (rng.normal(0.0, 0.5, (n_rows, 6)) for _ in range(3))
    sd = rng.uniform(0.0, 2.0, n_rows)
    servo.integral = rng.normal(0.0, 5.0, 6)   # the integral is added at the call
    at_row = backend.path_dynamics_rows(q, d1, d2, sd)
    for payload_kg in (0.0, 10.0):
        backend.set_control_payload(payload_kg)   # a blended move that starts with another load
        for i in (0, 7, ROWS_BLOCK - 1, ROWS_BLOCK, n_rows - 1, 3):
            b1, b2 = at_row(i)
            want_b1, want_b2 = backend.path_dynamics(q[i], d1[i], d2[i], float(sd[i]))
            assert np.array_equal(b1, want_b1) and np.array_equal(b2, want_b2), (payload_kg, i)


def test_path_dynamics_rows_follow_a_friction_change_in_the_middle_of_a_block() -> None:
    """The gearboxes' estimate changes the servo's friction every 0.1 s: a block computed before must add the new
    friction, not keep the old, and friction switched off and on again is followed too."""
    layer = make_virtual_motion_layer("irb2400", plant="realistic")
    backend, servo = layer.backend, layer.backend.loop.servo
    rng = np.random.default_rng(0)
    n_rows = ROWS_BLOCK + 30
    q, d1, d2 = (rng.uniform(-1.0, 1.0, (n_rows, 6)) for _ in range(3))
    sd = rng.uniform(0.0, 2.0, n_rows)
    at_row = backend.path_dynamics_rows(q, d1, d2, sd)
    frictions = [None, (np.full(6, 7.0), np.full(6, 3.0)), (None, None), (np.full(6, 2.0), np.full(6, 1.0))]
    for step, friction in enumerate(frictions):
        at_row(step)   # the first block computed with the friction before
        if friction is not None:
            servo.set_friction(*friction)
        for i in (step + 1, ROWS_BLOCK - 1 - step, n_rows - 1 - step):   # the same block, then the next
            b1, b2 = at_row(i)
            want_b1, want_b2 = backend.path_dynamics(q[i], d1[i], d2[i], float(sd[i]))
            assert np.allclose(b1, want_b1, rtol=0, atol=1e-9) and np.allclose(b2, want_b2, rtol=0, atol=1e-9), (step, i)
