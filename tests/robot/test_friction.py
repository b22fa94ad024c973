"""The joint friction law: Coulomb with a smoothed sign plus viscous, per joint."""

from __future__ import annotations

import numpy as np
import pytest

from orc_rpl.robot.friction import friction_torque_nm


@pytest.mark.parametrize("qd_rad_s, expected_nm", [
    pytest.param((0.0, 0.0), (0.0, 0.0), id="at rest: none"),
    pytest.param((1.0, -1.0), (40.0 + 60.0, -(4.0 + 3.0)), id="fast: full Coulomb against the motion plus viscous"),
    pytest.param((0.002, -0.002), (40.0 * np.tanh(1.0) + 0.12, -(4.0 * np.tanh(1.0) + 0.006)),
                 id="at the smoothing speed: tanh(1) of the Coulomb"),
])
def test_friction_torque(qd_rad_s: tuple[float, float], expected_nm: tuple[float, float]) -> None:
    torque = friction_torque_nm((40.0, 4.0), (60.0, 3.0), qd_rad_s, 0.002)
    assert torque == pytest.approx(expected_nm, abs=1e-9)
