"""Thermal load of the motors (thesis 2.4, 4.5): a first-order low-pass of the squared torque, built into the motion cycle."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from orc_rpl.errors import UsageError
from orc_rpl.plant import compiled

#: Continuous (thermal) torque as a share of the peak torque tau_max: AC servo motors are rated for
#: a peak of about three times their continuous torque. An *estimate*, the same for every joint.
CONTINUOUS_SHARE = 1.0 / 3.0

#: Thermal time constant of each motor (s), j1..j6 (more joints repeat the last one). *Estimates*,
#: chosen at the short end (the winding's own time constant; the motor housing adds minutes on a
#: real robot) so that a demonstration shows a motor heating up and cooling down in a minute or two
#: of simulated time: the large motors 20 s, the wrist motors 10 s.
TIME_CONSTANTS_S = (20.0, 20.0, 20.0, 10.0, 10.0, 10.0)

multiply, add = np.multiply, np.add


def estimate_kernels() -> Any:
    """The estimates' compiled updates (motion/estimate_kernels.py), None where numba is not there."""
    return compiled.kernels("orc_rpl.motion.estimate_kernels")



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
        self._kernels = estimate_kernels()

    @classmethod
    def for_arm(cls, tau_max_nm: Sequence[float], period_s: float) -> ThermalModel:
        """The documented estimates for an arm with these peak torques."""
        tau_max = np.asarray(tau_max_nm, dtype=float)
        n = len(tau_max)
        constants = [TIME_CONSTANTS_S[min(i, len(TIME_CONSTANTS_S) - 1)] for i in range(n)]
        return cls(CONTINUOUS_SHARE * tau_max, constants, period_s)

    def update(self, tau_nm: np.ndarray) -> None:
        """One period with the torque tau_nm (unchecked: the motion cycle calls this)."""
        if compiled.ON and self._kernels is not None:
            self._kernels.load_update(tau_nm, self._gain, self._decay, self.load)
            return
        work, load = self._work, self.load
        multiply(tau_nm, tau_nm, work)
        multiply(work, self._gain, work)
        multiply(load, self._decay, load)
        add(load, work, load)

    def reset(self) -> None:
        """Cold motors (a plant reset)."""
        self.load[:] = 0.0

    @property
    def kernels(self) -> Any:
        """The estimates' compiled updates (motion/estimate_kernels.py), None where numba is not there."""
        return self._kernels

    def kernel_state(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """What `estimate_kernels.load_update` reads and writes after the torque: the gain, the decay and the
        load (updated in place)."""
        return self._gain, self._decay, self.load


#: The drives' winding measurement is sampled every so many motion cycles (20 ms at 4 ms) ...
SAMPLE_EVERY_CYCLES = 5
#: ... and the estimate corrected every so many samples (0.1 s), from the resistance over them.
SAMPLES_PER_CORRECTION = 5
#: Samples below this current (A) are left out: the voltage's noise would dominate the resistance.
MIN_CURRENT_A = 2.0
#: While the model's rise is below this (K), the windings are at a known temperature: the measured
#: resistance calibrates R20 there (the model, a few percent off, is within about 0.1 K of the truth) ...
CALIBRATE_BELOW_K = 2.0
#: ... if the calibration's samples carried at least this sum of i^2 (A^2); else the model alone.
CALIBRATION_MIN_A2 = 200.0
#: A correction moves the model's rise S / (S + CORRECTION_A2) of the way to the measured one, S the
#: sum of i^2 (A^2) of its samples: much current, a precise resistance, a large step (an observer's gain).
CORRECTION_A2 = 2000.0


class WindingTemperature:
    """Estimated rise of each motor winding above ambient (K), from the torque of every motion cycle.

    dT/dt = (Rth R20 (1 + 0.00393 (T_ambient + T - 20)) (tau / k)^2 - T) / time_constant, with the data
    sheet's k (torque per ampere at the joint), R20, Rth and time constant, discretised exactly for a
    loss held over each period. The plant's own constants differ from the data sheet (docs/robots.md).

    With `measurement` set (a callable giving each drive's terminal voltage, current and the joint
    speed), the estimate is corrected online as drives do: the winding's resistance
    R = sum((V - k w) i) / sum(i^2) over a few samples gives its temperature through copper's
    coefficient, T = 20 + (R / R20 - 1) / 0.00393, with R20 measured at the cold start (while the
    model says the winding is still within CALIBRATE_BELOW_K of ambient); the model's rise moves
    a share of the way to the measured one every SAMPLE_EVERY_CYCLES * SAMPLES_PER_CORRECTION cycles
    (CORRECTION_A2). A winding that carried too little current while cold (CALIBRATION_MIN_A2) keeps
    the model alone; so does every winding without `measurement` (None).
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
        self._k = k
        self.measurement: Callable[[], tuple[np.ndarray, np.ndarray, np.ndarray]] | None = None
        self._kernels = estimate_kernels()
        self.reset()

    def update(self, tau_nm: np.ndarray) -> None:
        """One period with the torque tau_nm (in place, no allocation but for the measurement's cycles)."""
        if compiled.ON and self._kernels is not None:
            self._kernels.rise_update(tau_nm, self._gain, self._gain_per_k, self._decay, self.rise_k)
        else:
            work, heat, rise = self._work, self._heat, self.rise_k
            multiply(rise, self._gain_per_k, heat)
            add(heat, self._gain, heat)
            multiply(tau_nm, tau_nm, work)
            multiply(work, heat, work)
            multiply(rise, self._decay, rise)
            add(rise, work, rise)
        self.measure()

    def kernel_state(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """What `estimate_kernels.rise_update` reads and writes after the torque: the gain, its growth per
        kelvin, the decay and the rise (updated in place); the kernel's caller calls `measure` after it."""
        return self._gain, self._gain_per_k, self._decay, self.rise_k

    def measure(self) -> None:
        """The drives' measurement's part of a cycle (`update` runs it; so does the motion cycle's fused update of
        the estimates, gear_friction.update_estimates, after the model's part)."""
        if self.measurement is not None:
            self._cycles += 1
            if self._cycles % SAMPLE_EVERY_CYCLES == 0:
                self._sample(*self.measurement())

    def _sample(self, voltage_v: np.ndarray, current_a: np.ndarray, speed_rad_s: np.ndarray) -> None:
        """One sample of the drives' measurement: calibration at the cold start, then the correction."""
        self._samples += 1
        correct = self._samples % SAMPLES_PER_CORRECTION == 0
        if compiled.ON and self._kernels is not None:
            self._calibrating = self._kernels.winding_sample(
                current_a, voltage_v, self._k, speed_rad_s, self.rise_k, self._sums, self._flags, self._calibrating,
                correct, MIN_CURRENT_A, CALIBRATE_BELOW_K, CALIBRATION_MIN_A2, CORRECTION_A2, self._tempco,
                self._ambient_c)
            return
        # the reference of the kernel: in Python floats, joint by joint (six numbers: half the time of numpy's
        # calls on them), the same IEEE operations in the same order as the array formulas in the comments
        ohm_a2, a2 = [], []
        for c, v, k, w in zip(current_a.tolist(), voltage_v.tolist(), self._k.tolist(), speed_rad_s.tolist()):
            i = c if abs(c) >= MIN_CURRENT_A else c * 0.0   # i = current * (|current| >= MIN_CURRENT_A)
            ohm_a2.append((v - k * w) * i)                    # R i^2 of this sample
            a2.append(i * i)
        cal_num, cal_den, num, den = self._sums.tolist()
        calibrated, uncalibrated = self._flags.tolist()
        if self._calibrating:
            self._calibrate(ohm_a2, a2, cal_num, cal_den, calibrated, uncalibrated)
        for j, cal in enumerate(calibrated):
            if cal:
                num[j] += ohm_a2[j]
                den[j] += a2[j]
        if correct:
            # rise = 20 + (R / R20 - 1) / tempco - ambient; the estimate moves den / (den + CORRECTION_A2) of the way
            rise_k, tempco, ambient = self.rise_k.tolist(), self._tempco, self._ambient_c
            for j, (n, d, cn, cd) in enumerate(zip(num, den, cal_num, cal_den)):
                if d > 0.0:
                    r20 = cn / (cd if cd > 0.0 else 1.0)
                    rise = 20.0 + (n / d / r20 - 1.0) / tempco - ambient
                    rise_k[j] += d / (d + CORRECTION_A2) * (rise - rise_k[j])
                num[j] = den[j] = 0.0
            self.rise_k[:] = rise_k
        self._sums[:] = cal_num, cal_den, num, den
        self._flags[:] = calibrated, uncalibrated

    def _calibrate(self, ohm_a2: list[float], a2: list[float], cal_num: list[float], cal_den: list[float],
                   calibrated: list[bool], uncalibrated: list[bool]) -> None:
        """R20 from the resistance at the model's (known, near ambient) temperature, while the winding is cold."""
        tempco, ambient = self._tempco, self._ambient_c
        for j, rise in enumerate(self.rise_k.tolist()):
            if calibrated[j] or uncalibrated[j]:
                continue
            if rise < CALIBRATE_BELOW_K:   # cold
                cal_num[j] += ohm_a2[j] / (1.0 + tempco * (ambient + rise - 20.0))
                cal_den[j] += a2[j]
            elif cal_den[j] >= CALIBRATION_MIN_A2:
                calibrated[j] = True
            else:
                uncalibrated[j] = True   # too little current: the model alone
        self._calibrating = not all(c or u for c, u in zip(calibrated, uncalibrated))

    @property
    def r20_ohm(self) -> np.ndarray:
        """The winding resistances at 20 C measured at the cold start (NaN where not yet measured)."""
        cal_num, cal_den = self._sums[0], self._sums[1]
        return np.where(self._flags[0], cal_num / np.where(cal_den > 0.0, cal_den, 1.0), np.nan)

    def reset(self) -> None:
        """Windings at ambient (a cold start: the resistances are measured again)."""
        n = len(self.rise_k)
        self.rise_k[:] = 0.0
        self._cycles = self._samples = 0
        # the measurement's sums per joint (the calibration's R i^2 and i^2, the correction's) and flags
        # (calibrated, uncalibrated: too little current while cold), as `_sample` and its kernel keep them
        self._sums, self._flags = np.zeros((4, n)), np.zeros((2, n), dtype=bool)
        self._calibrating = True
