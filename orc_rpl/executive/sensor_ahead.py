"""The executive's room for motions computed ahead from sensor dummies (thesis 5.2): confirmed or corrected.

A motion that reads a sensor (`MOVE t TO OFFS(p, LaserSensor.Distance, 0, 0) WITH KNOWN = "almost"`) is
planned while the motion before it runs, with each sensor's dummy value (`SensorManager.dummies`). When the
statement runs, the real sensor answers and the request is made again:

* the same request: the plan is used as made (**confirmed**);
* the target moved by a translation of at most CORRECTION_LIMIT_M, nothing else changed: the plan made from
  the dummy is used, and the difference is a path correction that grows along the motion, smoothstep(s) times
  the difference, so the motion ends on the real target (**corrected**); an almost known motion's plan keeps
  10 % of the limits in reserve for such corrections;
* anything else: the motion layer plans it again when it starts.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np

from orc_rpl.application.runtime import MotionRequest, MotionView
from orc_rpl.world.pose import Pose

#: The largest correction of a target planned from a dummy (m); a larger one is planned again. The smoothstep
#: ramp's speed is 1.5 times the correction over the motion's duration: 15 mm/s for 10 mm over 1 s.
CORRECTION_LIMIT_M = 0.01


@dataclasses.dataclass(frozen=True, slots=True)
class Correction:
    """How the real request differs from the one planned from the dummies: a translation of the target (m, world)."""

    offset_m: tuple[float, float, float]

    def along(self) -> Callable[[MotionView], tuple[float, float, float]]:
        """The path correction at path coordinate s: smoothstep(s) times the offset (no step at the start)."""
        offset = np.array(self.offset_m)

        def correction(view: MotionView) -> tuple[float, float, float]:
            s = min(max(view.s, 0.0), 1.0)
            x, y, z = offset * (s * s * (3.0 - 2.0 * s))
            return (float(x), float(y), float(z))
        return correction


def correction(planned: MotionRequest, real: MotionRequest) -> Correction | None:
    """The correction that takes the plan made for `planned` to the target of `real`, or None when the two differ in
    more than a small translation of a pose target (or the request corrects its path itself, as TRACKMOVE does)."""
    a, b = planned.target, real.target
    if type(a) is not Pose or type(b) is not Pose or a.frame != b.frame or real.correction is not None:
        return None
    if dataclasses.replace(real, target=a, until=None) != dataclasses.replace(planned, until=None):
        return None
    ma, mb = a.matrix(), b.matrix()
    if not np.allclose(ma[:3, :3], mb[:3, :3], atol=1e-9, rtol=0.0):
        return None
    offset = mb[:3, 3] - ma[:3, 3]
    if float(np.linalg.norm(offset)) > CORRECTION_LIMIT_M:
        return None
    return Correction((float(offset[0]), float(offset[1]), float(offset[2])))
