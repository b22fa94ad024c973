"""Thermal load of the motors (thesis 2.4, 4.5): a first-order low-pass of the squared torque, built into the motion cycle."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from orc_rpl.errors import UsageError

#: Continuous (thermal) torque as a share of the peak torque tau_max: AC servo motors are rated for
#: a peak of about three times their continuous torque. An *estimate*, the same for every joint.
CONTINUOUS_SHARE = 1.0 / 3.0

#: Thermal time constant of each motor (s), j1..j6 (more joints repeat the last one). *Estimates*,
#: chosen at the short end (the winding's own time constant; the motor housing adds minutes on a
#: real robot) so that a demonstration shows a motor heating up and cooling down in a minute or two
#: of simulated time: the large motors 20 s, the wrist motors 10 s.
TIME_CONSTANTS_S = (20.0, 20.0, 20.0, 10.0, 10.0, 10.0)

multiply, add = np.multiply, np.add


class ThermalModel:
    """Per-joint thermal load x: dx/dt = ((tau / tau_continuous)^2 - x) / T, so x = 1 is the motor's limit.

    Discretised exactly for a torque held over each update period (zero-order hold):
    x <- a x + (1 - a) (tau / tau_c)^2 with a = exp(-period / T). The update works in preallocated
    arrays (four ufunc calls, no allocation): the motion layer runs it every motion cycle from the
    start of the run, with the last servo step's torque of that cycle.
    """

    def __init__(self, tau_continuous_nm: Sequence[float], time_constants_s: Sequence[float], period_s: float) -> None:
        tau_c = np.array(tau_continuous_nm, dtype=float)
        t = np.array(time_constants_s, dtype=float)
        if tau_c.shape != t.shape or tau_c.ndim != 1:
            raise UsageError("one continuous torque and one time constant per joint")
        if not (np.all(np.isfinite(tau_c)) and np.all(tau_c > 0) and np.all(np.isfinite(t)) and np.all(t > 0)):
            raise UsageError("continuous torques and thermal time constants must be positive numbers")
        if not period_s > 0:
            raise UsageError(f"the thermal model's period must be positive, got {period_s}")
        self.tau_continuous_nm = tau_c
        self.time_constants_s = t
        self.period_s = float(period_s)
        self._decay = np.exp(-self.period_s / t)                     #: a
        self._gain = (1.0 - self._decay) / (tau_c * tau_c)           #: (1 - a) / tau_c^2
        self._work = np.zeros(len(t))
        self.load = np.zeros(len(t))  #: the estimate, 1.0 = the motor's continuous limit (updated in place)

    @classmethod
    def for_arm(cls, tau_max_nm: Sequence[float], period_s: float) -> ThermalModel:
        """The documented estimates for an arm with these peak torques."""
        tau_max = np.asarray(tau_max_nm, dtype=float)
        n = len(tau_max)
        constants = [TIME_CONSTANTS_S[min(i, len(TIME_CONSTANTS_S) - 1)] for i in range(n)]
        return cls(CONTINUOUS_SHARE * tau_max, constants, period_s)

    def update(self, tau_nm: np.ndarray) -> None:
        """One period with the torque tau_nm (unchecked: the motion cycle calls this)."""
        work, load = self._work, self.load
        multiply(tau_nm, tau_nm, work)
        multiply(work, self._gain, work)
        multiply(load, self._decay, load)
        add(load, work, load)

    def reset(self) -> None:
        """Cold motors (a plant reset)."""
        self.load[:] = 0.0
