"""The arm-control room's external axes in the path coordinate: one stage per axis, combined with the arm's (thesis fig. 5.6).

Bit-slice style: every stage is handed the same path state (t, s, s', s'') the arm's controller has; each
answers the range of s'' its own limits allow there and the time lag of its drive; the path velocity
controller takes the most restrictive range of all the stages, so the arm and its external axes keep one
time scale and stay on one path.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from orc_rpl.arm.pvc import PathDynamics, PathFunction, PathOrders, PathVelocityController, PvcSettings

#: e(x, order): an external axis' value along the path parameter x (order 0) and its first two derivatives by x.
AxisProfile = Callable[[float, int], float]


@dataclass(frozen=True, slots=True)
class AxisLimits:
    """What one external axis' drive can do (m or rad; per second)."""

    speed_si: float
    acceleration_si: float
    lag_s: float = 0.0   #: how long after its reference the axis follows (what its drive's lead leaves; 0: none)


class ExternalAxisStage:
    """One external axis driven from the path coordinate: its reference and its admissible range of s''."""

    def __init__(self, name: str, profile: AxisProfile, limits: AxisLimits) -> None:
        self.name, self.profile, self.limits = name, profile, limits

    def reference(self, x: float, sd: float, sdd: float) -> tuple[float, float, float]:
        """The axis' (position, speed, acceleration) at path state (x, s', s''): e, e' s', e'' s'^2 + e' s''."""
        e, d1, d2 = (self.profile(x, order) for order in (0, 1, 2))
        return e, d1 * sd, d2 * sd * sd + d1 * sdd

    def admissible(self, x: float, sd: float) -> tuple[float, float]:
        """The range of s'' within the axis' acceleration limit at (x, s'); (-inf, inf) where it does not move.

        Above the axis' speed limit the range asks for deceleration only (its upper end is at most 0).
        """
        d1, d2 = self.profile(x, 1), self.profile(x, 2)
        a_max = self.limits.acceleration_si
        if abs(d1) < 1e-12:
            return -math.inf, math.inf
        r1, r2 = (-a_max - d2 * sd * sd) / d1, (a_max - d2 * sd * sd) / d1
        lo, hi = min(r1, r2), max(r1, r2)
        if abs(d1 * sd) > self.limits.speed_si * (1.0 + 1e-9):
            hi = min(hi, 0.0)
        return lo, hi

    def lag_s(self) -> float:
        """The time lag of the axis' drive (its controller leads its reference by this much)."""
        return self.limits.lag_s


def combine(ranges: Sequence[tuple[float, float]]) -> tuple[float, float]:
    """The most restrictive range of s'': the largest lower end and the smallest upper end (lo > hi: none fits)."""
    return max((lo for lo, _ in ranges), default=-math.inf), min((hi for _, hi in ranges), default=math.inf)


class StagedPathVelocityController(PathVelocityController):
    """The arm's path velocity controller with external axis stages: the admissible range is the combined one."""

    def __init__(self, path: PathFunction, x_f: np.ndarray, sd_f: np.ndarray, sub: int, servo_period_s: float,
                 dynamics: PathDynamics | None, tau_max: np.ndarray, stages: Sequence[ExternalAxisStage],
                 settings: PvcSettings = PvcSettings(), path_orders: PathOrders | None = None) -> None:
        self.stages = tuple(stages)
        super().__init__(path, x_f, sd_f, sub, servo_period_s, dynamics or _no_dynamics, tau_max, settings,
                         path_orders=path_orders)

    def admissible(self, x: float, sd: float, cycle: int | None = None) -> tuple[float, float]:
        arm = super().admissible(x, sd, cycle)
        return combine([arm, *(stage.admissible(x, sd) for stage in self.stages)])

    def lag_s(self) -> float:
        """The time lag through the stages: the largest of the arm's and each axis' own (thesis 5.3)."""
        return max(super().lag_s(), *(stage.lag_s() for stage in self.stages))


def _no_dynamics(q: np.ndarray, d1: np.ndarray, d2: np.ndarray, sd: float) -> tuple[np.ndarray, np.ndarray]:
    """A backend without a model of its arm (a kinematic follower): no torque limits the time scale."""
    zero: Any = np.zeros_like(q)
    return zero, zero
