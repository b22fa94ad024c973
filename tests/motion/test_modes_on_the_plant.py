"""OFF, BLOCK and back to RUN on the realistic plant: drives off with the brakes holding, a held arm, no jumps."""

from __future__ import annotations

import numpy as np
import pytest

from orc_rpl.motion import JointMotion, Params, make_virtual_motion_layer
from orc_rpl.motion.specs import Mode, MoveStatus

pytestmark = pytest.mark.sim


def _cycles(layer: object, n: int) -> None:
    for _ in range(n):
        layer.tick()  # type: ignore[attr-defined]


def test_off_switches_the_drives_off_and_the_brakes_hold_the_arm() -> None:
    layer = make_virtual_motion_layer("irb2400", plant="realistic", seed=1)
    loop = layer.backend.loop
    loop.set_payload(12.0, known=False)
    layer.wait(layer.move(JointMotion(tuple(np.radians((30, 20, -10, 0, 40, 0)))), Params()))
    layer.set_mode(Mode.OFF)
    held = loop.cell.true_q.copy()
    _cycles(layer, 500)  # two seconds
    assert np.all(loop.cell.tau == 0.0), "no torque from the drives"
    assert loop.cell.brakes_engaged
    assert np.max(np.abs(loop.cell.true_q - held)) < 1e-4, "the brakes hold the arm against gravity"
    h = layer.move(JointMotion(tuple(layer.kin.arm.home_q)), Params())
    assert h.status is MoveStatus.ILLEGAL


def test_leaving_off_holds_the_arm_where_it_is_and_it_moves_again() -> None:
    layer = make_virtual_motion_layer("irb2400", plant="realistic", seed=1)
    loop = layer.backend.loop
    layer.wait(layer.move(JointMotion(tuple(np.radians((30, 20, -10, 0, 40, 0)))), Params()))
    layer.set_mode(Mode.OFF)
    _cycles(layer, 100)
    held = loop.cell.true_q.copy()
    layer.set_mode(Mode.RUN)
    assert not loop.cell.brakes_engaged
    _cycles(layer, 250)
    assert np.max(np.abs(loop.cell.true_q - held)) < 2e-4, "no jump when the drives take over from the brakes"
    h = layer.move(JointMotion(tuple(layer.kin.arm.home_q)), Params())
    layer.wait(h)
    assert h.status is MoveStatus.READY and h.settled


def test_block_holds_the_arm_at_standstill_with_the_drives_on() -> None:
    layer = make_virtual_motion_layer("irb2400", plant="realistic", seed=1)
    loop = layer.backend.loop
    h = layer.move(JointMotion(tuple(np.radians((60, 20, -10, 0, 40, 0)))), Params())
    _cycles(layer, 100)  # on the way
    layer.set_mode(Mode.BLOCK)
    _cycles(layer, 500)  # braked on the path, settled
    still = loop.cell.true_q.copy()
    _cycles(layer, 250)
    assert h.status is MoveStatus.ACT_STOPPED
    assert not loop.cell.brakes_engaged and np.any(loop.cell.tau != 0.0), "the drives hold the arm"
    assert np.max(np.abs(loop.cell.true_q - still)) < 1e-5
    assert np.max(np.abs(loop.cell.qd)) < 1e-2
    assert layer.move(JointMotion(tuple(layer.kin.arm.home_q)), Params()).status is MoveStatus.ILLEGAL
