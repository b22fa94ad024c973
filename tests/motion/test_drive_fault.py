"""A drive that fails under the motion layer (a real arm's DriveFault): the moves fail with it, the arm is held."""

from __future__ import annotations

import numpy as np
import pytest

from orc_rpl.errors import DriveFault
from orc_rpl.motion import JointMotion, MoveStatus, make_virtual_motion_layer


def failing_after(layer, cycles: int) -> None:  # noqa: ANN001
    """Make the layer's backend raise DriveFault from its `cycles`-th advance on (as a bus backend does)."""
    backend = layer.backend
    advance = backend.advance
    count = [0]

    def advance_or_fail(q_ref: np.ndarray, qd_ref: np.ndarray, qdd_ref: np.ndarray) -> None:
        count[0] += 1
        if count[0] >= cycles:
            raise DriveFault("servo 3 (joint 3): does not answer on /dev/ttyUSB0; the other joints hold their positions")
        advance(q_ref, qd_ref, qdd_ref)

    backend.advance = advance_or_fail


def test_a_drive_fault_fails_the_running_and_queued_moves_and_holds_where_the_arm_is() -> None:
    layer = make_virtual_motion_layer(backend="kinematic")
    q0 = layer.current_q()
    first = layer.move(JointMotion(tuple(q0 + 0.3)))
    second = layer.move(JointMotion(tuple(q0)))
    failing_after(layer, 20)
    layer.wait(second)
    assert first.status is MoveStatus.FAULT and second.status is MoveStatus.FAULT
    assert isinstance(first.error, DriveFault) and "servo 3 (joint 3)" in str(first.error)
    assert layer.idle()
    np.testing.assert_array_equal(layer.reference_q(), layer.current_q())  # the reference is where the arm stopped


def test_a_drive_fault_with_no_move_to_carry_it_reaches_the_caller() -> None:
    layer = make_virtual_motion_layer(backend="kinematic")
    failing_after(layer, 1)
    with pytest.raises(DriveFault, match="servo 3"):
        layer.tick()
