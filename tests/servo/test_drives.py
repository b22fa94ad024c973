"""The servo law run in C inside the realistic plant's drives agrees with the Python law it is written from."""

from __future__ import annotations

import numpy as np
import pytest

from orc_rpl.motion import JointMotion, Params, make_virtual_motion_layer

pytestmark = pytest.mark.sim

#: How far the TCP of the plant driven by the C law may be from the TCP driven by the Python law,
#: step for step while the arm moves (docs/robots.md, "The drives"), and at the end of the move.
MOVING_TOLERANCE_MM, END_TOLERANCE_MM = 0.05, 0.005


def _move(compiled: bool, seed: int = 3) -> tuple[np.ndarray, list[float]]:
    """The plant's own joint angles every motion cycle of one fast move with an undeclared payload."""
    layer = make_virtual_motion_layer("irb2400", plant="realistic", seed=seed)
    loop = layer.backend.loop
    loop.use_compiled_law(compiled)
    loop.set_payload(12.0, known=False)
    h = layer.move(JointMotion(tuple(np.radians((60, 20, -20, 40, -60, 90)))), Params(load_kg=10.0))
    angles, tcp = [], []
    while not h.done:
        layer.tick()
        angles.append(loop.cell.true_q.copy())
        tcp.append(layer.kin.arm.fk(angles[-1])[:3, 3])
    return np.array(angles), tcp


def test_the_drives_in_c_follow_the_python_servo_law_within_the_stated_tolerance() -> None:
    compiled, tcp_c = _move(True)
    python, tcp_py = _move(False)
    n = min(len(compiled), len(python))
    worst_mm = max(float(np.linalg.norm(a - b)) for a, b in zip(tcp_c[:n], tcp_py[:n])) * 1000.0
    assert worst_mm < MOVING_TOLERANCE_MM, worst_mm
    assert float(np.linalg.norm(tcp_c[-1] - tcp_py[-1])) * 1000.0 < END_TOLERANCE_MM
    assert abs(len(compiled) - len(python)) <= 2, "the move settles at about the same cycle"


def test_the_drives_in_c_are_deterministic_for_a_seed() -> None:
    a, _ = _move(True, seed=5)
    b, _ = _move(True, seed=5)
    assert np.array_equal(a, b)


def test_switching_between_the_laws_is_bumpless() -> None:
    layer = make_virtual_motion_layer("irb2400", plant="realistic", seed=1)
    loop = layer.backend.loop
    loop.set_payload(8.0, known=False)   # the integral carries the weight the model does not know
    layer.wait(layer.move(JointMotion(tuple(np.radians((20, 10, -10, 0, 20, 0)))), Params()))
    held = loop.cell.true_q.copy()
    for compiled in (False, True, False):
        loop.use_compiled_law(compiled)
        state = loop.hold(layer.reference_q(), 200)
        assert np.max(np.abs(loop.cell.true_q - held)) < 1e-4, f"compiled={compiled}: the arm stays where it was"
        assert np.max(np.abs(state.position_error)) < 1e-4
