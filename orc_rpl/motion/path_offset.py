"""A tracked move's path correction as the servo gets it: a joint offset, on elastic gears a smooth trajectory."""

from __future__ import annotations

import numpy as np

#: How fast a correction is taken up on elastic gears: the three poles of its filter (rad/s). Hand runs of the thesis
#: weld on the IRB 2400's elastic gears (the laser's RMS error, the tracker modelling the filter): 80, 120, 135, 150,
#: 165, 180, 200 rad/s gave 0.58, 0.48, 0.46, 0.46, 0.47, 0.50, 0.66 mm.
CORRECTION_OMEGA_RAD_S = 150.0


def correction_omega_rad_s(averaging_s: float) -> float | None:
    """The filter of corrections (rad/s) for a motion layer that averages moves from rest over `averaging_s` (its
    smoothing windows' sum): smoothed wherever moves from rest are (elastic gears), None (a step) elsewhere."""
    return CORRECTION_OMEGA_RAD_S if averaging_s > 0.0 else None


class PathOffset:
    """A joint offset that follows its goal through a critically damped filter of three poles at `omega_rad_s`,
    servo step by servo step, with its speed and acceleration for the servo's feed-forward; omega None: the goal
    itself, a step.

    On elastic gears a step of the reference rings the links (a 1 mm correction during a move: 1.80 mm sideways at
    most, 1.25 smoothed). Smoothed without its speed and acceleration fed forward, or through two poles (whose
    acceleration steps at each new goal: a torque step into the gears), the thesis weld lost its seam."""

    def __init__(self, n: int, omega_rad_s: float | None) -> None:
        self.omega_rad_s = omega_rad_s
        self.goal = np.zeros(n)     #: where the offset is going (rad per joint)
        self.q = np.zeros(n)        #: the offset the servo was given last (rad)
        self.qd = np.zeros(n)
        self.qdd = np.zeros(n)

    def rows(self, n: int, dt_s: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The offset's next n servo steps of dt_s: position, speed, acceleration, each (n, joints)."""
        if self.omega_rad_s is None:
            self.q = self.goal.copy()
            zero = np.zeros((n, len(self.goal)))
            return np.tile(self.goal, (n, 1)), zero, zero
        w = self.omega_rad_s
        out = np.empty((3, n, len(self.goal)))
        q, qd, qdd = self.q, self.qd, self.qdd
        for i in range(n):  # semi-implicit Euler; w * dt_s = 0.15 at 1 ms
            jerk = w ** 3 * (self.goal - q) - 3.0 * w * w * qd - 3.0 * w * qdd
            qdd = qdd + jerk * dt_s
            qd = qd + qdd * dt_s
            q = q + qd * dt_s
            out[0, i], out[1, i], out[2, i] = q, qd, qdd
        self.q, self.qd, self.qdd = q, qd, qdd
        return out[0], out[1], out[2]
