"""The drives' work rows follow the servo's friction as it changes (the gearboxes' estimate, every 0.1 s)."""

from __future__ import annotations

import numpy as np
import pytest

from orc_rpl.motion import make_virtual_motion_layer

pytestmark = pytest.mark.sim


def _run(rows_made_again: bool, elastic: bool) -> np.ndarray:
    """40 servo calls of 4 or 5 steps with the friction changed, switched off and on; the measured states."""
    layer = make_virtual_motion_layer("irb2400", plant="realistic", seed=3, elastic=elastic, gear_feedforward=elastic)
    loop = layer.backend.loop
    q0, rng, states = np.array(loop.cell.q), np.random.default_rng(5), []
    for call in range(40):
        n_steps = 4 if call % 7 else 5
        if call % 5 == 2:
            loop.servo.set_friction(rng.uniform(5.0, 50.0, 6), rng.uniform(1.0, 60.0, 6))
        if call == 23:
            loop.servo.set_friction(None, None)
        if rows_made_again:
            loop.drives._rows_for(n_steps)   # the way it was: every array made again for the friction now
        t = np.linspace(0.0, 1.0, n_steps)[:, None]
        state = loop.run(q0 + 0.002 * (call + t), np.full((n_steps, 6), 0.5), np.zeros((n_steps, 6)), n_steps)
        states.append(np.concatenate([state.q, state.qd, state.tau, loop.servo.integral]))
    return np.array(states)


@pytest.mark.parametrize("elastic", [False, True], ids=["rigid", "elastic"])
def test_a_friction_change_gives_what_rows_made_again_give(elastic: bool) -> None:
    assert np.array_equal(_run(False, elastic), _run(True, elastic))
