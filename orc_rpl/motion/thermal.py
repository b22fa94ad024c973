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


class WindingTemperature:
    """Estimated rise of each motor winding above ambient (K), from the torque of every motion cycle.

    dT/dt = (Rth R20 (1 + 0.00393 (T_ambient + T - 20)) (tau / k)^2 - T) / time_constant, with the data
    sheet's k (torque per ampere at the joint), R20, Rth and time constant, discretised exactly for a
    loss held over each period. The plant's own constants differ from the data sheet (docs/robots.md).
    """

    def __init__(self, torque_per_amp_nm_a: Sequence[float], resistance_ohm: Sequence[float], rth_k_w: Sequence[float],
                 time_constants_s: Sequence[float], ambient_c: float, period_s: float, tempco_1_k: float) -> None:
        arrays = [np.array(v, dtype=float) for v in (torque_per_amp_nm_a, resistance_ohm, rth_k_w, time_constants_s)]
        if len({a.shape for a in arrays}) != 1 or not all(np.all(np.isfinite(a)) and np.all(a > 0) for a in arrays):
            raise UsageError("winding estimate: one positive torque constant, resistance, Rth and time constant per joint")
        k, self._r20, self._rth, t = arrays
        self._inv_k2 = 1.0 / (k * k)
        self._decay = np.exp(-period_s / t)
        self._ambient_c, self._tempco = float(ambient_c), float(tempco_1_k)
        # steady rise per (tau/k)^2 at 20 C and its growth per kelvin, folded with (1 - a): four ufuncs a cycle
        self._gain = (1.0 - self._decay) * self._rth * self._r20 * self._inv_k2 * (1.0 + self._tempco * (self._ambient_c - 20.0))
        self._gain_per_k = (1.0 - self._decay) * self._rth * self._r20 * self._inv_k2 * self._tempco
        self._work, self._heat = np.zeros(len(k)), np.zeros(len(k))
        self.rise_k = np.zeros(len(k))  #: the estimate (K above ambient)

    def update(self, tau_nm: np.ndarray) -> None:
        """One period with the torque tau_nm (in place, no allocation)."""
        work, heat, rise = self._work, self._heat, self.rise_k
        multiply(rise, self._gain_per_k, heat)
        add(heat, self._gain, heat)
        multiply(tau_nm, tau_nm, work)
        multiply(work, heat, work)
        multiply(rise, self._decay, rise)
        add(rise, work, rise)

    def reset(self) -> None:
        """Windings at ambient."""
        self.rise_k[:] = 0.0
