"""The robot room's joint friction law: the torque a joint's Coulomb and viscous friction take at a speed.

Written once for every estimate of it (the controller's warm-up estimate, the arm's force from its motor
torques, the payload fit's friction change): Coulomb friction c with its sign smoothed over a speed
`sign_smooth_rad_s`, plus viscous friction b,

    tau = c tanh(qd / sign_smooth_rad_s) + b qd

The smoothing belongs to the caller (an estimate of the torque a joint needs smooths over a few mrad/s; the
servo's feed-forward over more, for its stability).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np


def friction_torque_nm(coulomb_nm: np.ndarray | Sequence[float], viscous_nm_s: np.ndarray | Sequence[float],
                       qd_rad_s: np.ndarray | Sequence[float], sign_smooth_rad_s: float) -> np.ndarray:
    """The friction torque per joint at speeds qd (N m, opposing the motion: add it to the drive's torque)."""
    qd = np.asarray(qd_rad_s, dtype=float)
    return np.asarray(coulomb_nm, dtype=float) * np.tanh(qd / sign_smooth_rad_s) + np.asarray(viscous_nm_s, dtype=float) * qd
