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
