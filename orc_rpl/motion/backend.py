"""The seam below the motion layer: what drives the joints (a servo and plant, or a perfect kinematic follower)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

import numpy as np


class Backend(Protocol):
    """Runs the servo steps of one motion cycle and reports the measured state."""

    servo_period_s: float  #: one servo step (1 ms on the virtual robot)

    def advance(self, q_ref: np.ndarray, qd_ref: np.ndarray, qdd_ref: np.ndarray) -> None:
        """Run len(q_ref) servo steps, row i of each (steps, n) array being step i's reference."""
        ...

    def q(self) -> np.ndarray:
        """Measured joint positions."""
        ...

    def qd(self) -> np.ndarray:
        """Measured joint velocities."""
        ...

    def torque(self) -> np.ndarray:
        """Joint torques now applied (measured, or the controller's estimate)."""
        ...

    def time_s(self) -> float:
        """The controller clock."""
        ...

    def reset(self, q: np.ndarray) -> None:
        """Put the joints at q, at rest (simulation only; a real robot refuses)."""
        ...


class KinematicBackend:
    """Follows the reference perfectly: for fast tests, planning previews and a recording robot."""

    def __init__(
        self,
        q0: np.ndarray,
        servo_period_s: float = 0.001,
        inverse_dynamics: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray] | None = None,
    ) -> None:
        self.servo_period_s = servo_period_s
        self._q = np.array(q0, dtype=float)
        self._qd = np.zeros_like(self._q)
        self._qdd = np.zeros_like(self._q)
        self._steps = 0
        self._inverse_dynamics = inverse_dynamics

    def advance(self, q_ref: np.ndarray, qd_ref: np.ndarray, qdd_ref: np.ndarray) -> None:
        self._q = q_ref[-1].copy()
        self._qd = qd_ref[-1].copy()
        self._qdd = qdd_ref[-1].copy()
        self._steps += len(q_ref)

    def q(self) -> np.ndarray:
        return self._q

    def qd(self) -> np.ndarray:
        return self._qd

    def torque(self) -> np.ndarray:
        # computed only when someone asks: most cycles nobody does
        if self._inverse_dynamics is None:
            return np.zeros_like(self._q)
        return self._inverse_dynamics(self._q, self._qd, self._qdd)

    def time_s(self) -> float:
        return self._steps * self.servo_period_s

    def reset(self, q: np.ndarray) -> None:
        self._q = np.array(q, dtype=float)
        self._qd[:] = 0.0
        self._qdd[:] = 0.0
