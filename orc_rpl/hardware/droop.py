"""The hardware room's droop correction: the host's slow integral around bus servos whose own loops droop under load."""

from __future__ import annotations

import numpy as np

#: Counts of the reference-minus-measured error left alone: the servo's dead zone (a count) and a count more.
DEAD_COUNTS = 1.5
#: Share of the error added to the goal's offset each motion cycle while the reference is at rest (a time
#: constant of some 20 cycles: slow beside the servo's own loop, so the two do not fight).
GAIN_PER_CYCLE = 0.05
#: The offset never exceeds this (counts): the droop of a servo at its full load, not a runaway.
LIMIT_COUNTS = 24.0
#: A joint slower than this is at rest (rad/s): its error is droop, not lag.
AT_REST_RAD_S = 0.02
#: A FINE move has arrived within this many counts (the correction's dead band plus the encoder's count).
SETTLED_COUNTS = 2.0


class DroopCorrection:
    """Goals the servos are sent: the reference plus an offset that takes out the droop where the arm stops.

    A bus servo's position loop is proportional: it droops by load / gain, a few counts on a desktop arm's
    shoulder (docs/hardware.md). While the reference is at rest (a FINE point, a hold), the host adds a
    share of the measured error to the offset each cycle, so the arm reaches the reference within a count
    or two; the offset is kept while the arm moves (the load changes slowly along a path).
    """

    def __init__(self, n_joints: int, rad_per_count: float) -> None:
        self.offset_rad = np.zeros(n_joints)
        self._rad = rad_per_count
        self._last_ref: np.ndarray | None = None

    def goal(self, q_ref: np.ndarray, q_measured: np.ndarray, qd_measured: np.ndarray) -> np.ndarray:
        """The goal to send for this cycle's reference, given the last measured position and speed."""
        rad = self._rad
        if self._last_ref is not None and np.all(np.abs(q_ref - self._last_ref) < 0.1 * rad):
            error = q_ref - q_measured
            # only a joint at rest near its reference droops: one still arriving would wind the offset up
            error[(np.abs(error) <= DEAD_COUNTS * rad) | (np.abs(error) > LIMIT_COUNTS * rad)
                  | (np.abs(qd_measured) > AT_REST_RAD_S)] = 0.0
            self.offset_rad = np.clip(self.offset_rad + GAIN_PER_CYCLE * error, -LIMIT_COUNTS * rad, LIMIT_COUNTS * rad)
        self._last_ref = np.array(q_ref, dtype=float)
        return q_ref + self.offset_rad

    def clear(self) -> None:
        """Forget the offset (the arm was put somewhere else, or its torque was off)."""
        self.offset_rad[:] = 0.0
        self._last_ref = None
