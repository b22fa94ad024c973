"""The controller's estimate of its gearboxes' warm-up and the joint friction that follows from it, every motion cycle.

A cold gearbox has more friction than a warm one: the class figures of the robot (docs/robots.md, "The
realistic plant") give the friction at ambient as `cold_friction_factor` times the warm one, the excess
falling as exp(-rise / warm_rise_k) with the gearbox's temperature rise. The rise follows
dT/dt = (P - T / Rth) / (Rth Cth), P the friction power (Coulomb |qd| + viscous qd^2 at the estimated
friction) plus `gear_motor_heat_share` of the winding's copper loss (the data sheet's resistance at the
winding estimate's temperature). The controller integrates that law from the joint torques and speeds
it measures, as it integrates its winding estimate: it has no gearbox thermometer, so it assumes a cold
start (a reset) unless told otherwise (`warm_up`).

What it is for: the friction's *change* between two moments (`change_since`), which IDENTMOVE takes off a
lift against its tare (the warm-up between them would otherwise read as kilograms). Its absolute level is
the nominal friction times the factor; the plant's own warm friction differs from the nominal by up to
about 10 %, so the change is known to about that share (CHANGE_SPREAD).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from orc_rpl.errors import UsageError
from orc_rpl.motion.thermal import ThermalModel, WindingTemperature, estimate_kernels
from orc_rpl.plant import compiled
from orc_rpl.robot.friction import friction_torque_nm

#: The rise is integrated every so many motion cycles (0.1 s at 4 ms) from the cycles' mean heat: its time
#: constant is 20 minutes, and a cycle then costs three in-place sums.
UPDATE_EVERY_CYCLES = 25
#: The share of a predicted friction change the estimate may be off by: the plant's warm friction is
#: within about 10 % of the nominal one, and the gearbox rise is integrated with the estimated friction.
CHANGE_SPREAD = 0.2

#: Speed (rad/s) over which the estimate's Coulomb friction turns from one sign to the other: the plant's is
#: sharp (full at a few mrad/s), the measured speed's noise is 0.2 mrad/s. (The servo's feed-forward smooths
#: over 0.05 rad/s for its stability; an estimate of the torque the joint needs must not.)
SIGN_SMOOTH_RAD_S = 0.002


@dataclass(frozen=True, slots=True)
class FrictionState:
    """The estimated joint friction at one moment: Coulomb (N m) and viscous (N m s/rad) per joint."""

    time_s: float
    coulomb_nm: tuple[float, ...]
    viscous_nm_s: tuple[float, ...]


@dataclass(frozen=True, slots=True)
class FrictionChange:
    """The friction's change between two moments, per joint, and how far it may be off (1 sigma)."""

    coulomb_nm: tuple[float, ...]
    viscous_nm_s: tuple[float, ...]
    coulomb_sigma_nm: tuple[float, ...]
    viscous_sigma_nm_s: tuple[float, ...]


class GearFriction:
    """Per-joint gearbox rise above ambient (K) and the friction it gives, integrated every motion cycle."""

    def __init__(self, coulomb_nm: Sequence[float], viscous_nm_s: Sequence[float], gear_rth_k_w: Sequence[float],
                 gear_time_constant_s: float, cold_friction_factor: float, warm_rise_k: float,
                 motor_heat_share: float, torque_per_amp_nm_a: Sequence[float], resistance_ohm: Sequence[float],
                 tempco_1_k: float, ambient_c: float, period_s: float) -> None:
        arrays = [np.array(v, dtype=float) for v in (coulomb_nm, viscous_nm_s, gear_rth_k_w, torque_per_amp_nm_a,
                                                      resistance_ohm)]
        if len({a.shape for a in arrays}) != 1 or not all(np.all(np.isfinite(a)) and np.all(a >= 0) for a in arrays):
            raise UsageError("gear friction estimate: one non-negative friction, Rth, torque constant and resistance per joint")
        if not (gear_time_constant_s > 0 and warm_rise_k > 0 and cold_friction_factor >= 1.0 and period_s > 0):
            raise UsageError("gear friction estimate: positive time constant, rise and period; cold factor at least 1")
        self._coulomb, self._viscous, self._rth, k, self._r20 = arrays
        self._inv_k2 = 1.0 / (k * k)
        self._decay = float(np.exp(-period_s / gear_time_constant_s))
        self._excess, self._warm_rise_k = cold_friction_factor - 1.0, float(warm_rise_k)
        self._share, self._tempco, self._ambient_c = float(motor_heat_share), float(tempco_1_k), float(ambient_c)
        self.rise_k = np.zeros(len(k))  #: the estimate (K above ambient)
        self._work, self._speed_sum, self._speed_sq_sum, self._tau_sq_sum = (np.zeros(len(k)) for _ in range(4))
        self._kernels = estimate_kernels()
        self._cycles = 0
        #: Told the friction (Coulomb N m, viscous N m s/rad) each time the estimate changes (None: nobody):
        #: the servo's friction feed-forward on elastic gears (motion/virtual.py)
        self.listener: Callable[[np.ndarray, np.ndarray], None] | None = None

    def _tell(self) -> None:
        """The listener gets the friction now (after each change of the estimate)."""
        if self.listener is not None:
            self.listener(*self.friction_nm())

    @property
    def warm_nm(self) -> tuple[np.ndarray, np.ndarray]:
        """The nominal warm (Coulomb N m, viscous N m s/rad) friction: the controller's model without the warm-up."""
        return self._coulomb.copy(), self._viscous.copy()

    @property
    def factor(self) -> np.ndarray:
        """Friction now over warm friction, per joint."""
        return 1.0 + self._excess * np.exp(-self.rise_k / self._warm_rise_k)

    def friction_nm(self) -> tuple[np.ndarray, np.ndarray]:
        """The estimated (Coulomb N m, viscous N m s/rad) friction now."""
        f = self.factor
        return self._coulomb * f, self._viscous * f

    def torque_nm(self, qd_rad_s: np.ndarray) -> np.ndarray:
        """The friction torque the joints need at these speeds now (N m, opposing the motion: add it to the drive's)."""
        return friction_torque_nm(*self.friction_nm(), qd_rad_s, SIGN_SMOOTH_RAD_S)

    def update(self, tau_nm: np.ndarray, qd_rad_s: np.ndarray, winding_rise_k: np.ndarray | None = None) -> None:
        """One motion cycle with the measured torque and speed (the winding's estimated rise for its resistance).

        The cycle only sums |qd|, qd^2 and tau^2 in place (a few microseconds); the rise, whose time constant
        is 20 minutes, is integrated from their means every UPDATE_EVERY_CYCLES cycles."""
        if compiled.ON and self._kernels is not None:
            self._kernels.sums_update(tau_nm, qd_rad_s, self._speed_sum, self._speed_sq_sum, self._tau_sq_sum)
        else:
            work = self._work
            np.abs(qd_rad_s, out=work)
            np.add(self._speed_sum, work, out=self._speed_sum)
            np.multiply(work, work, out=work)
            np.add(self._speed_sq_sum, work, out=self._speed_sq_sum)
            np.multiply(tau_nm, tau_nm, out=work)
            np.add(self._tau_sq_sum, work, out=self._tau_sq_sum)
        self.count(winding_rise_k)

    def kernel_state(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """What `estimate_kernels.sums_update` adds the cycle's |qd|, qd^2 and tau^2 to (in place); the kernel's
        caller calls `count` after it."""
        return self._speed_sum, self._speed_sq_sum, self._tau_sq_sum

    def count(self, winding_rise_k: np.ndarray | None) -> None:
        """A cycle summed (`update` runs it after the sums; so does `update_estimates`): the rise integrated every
        UPDATE_EVERY_CYCLES cycles."""
        self._cycles += 1
        if self._cycles == UPDATE_EVERY_CYCLES:
            self._integrate(winding_rise_k)

    def _integrate(self, winding_rise_k: np.ndarray | None) -> None:
        """The rise over the cycles summed since the last time, from their mean heat."""
        n, self._cycles = self._cycles, 0
        coulomb, viscous = self.friction_nm()
        rise_w = 0.0 if winding_rise_k is None else winding_rise_k
        copper_w = self._r20 * (1.0 + self._tempco * (self._ambient_c + rise_w - 20.0)) * self._inv_k2 * self._tau_sq_sum / n
        heat_w = (coulomb * self._speed_sum + viscous * self._speed_sq_sum) / n + self._share * copper_w
        decay = self._decay ** n
        self.rise_k = decay * self.rise_k + (1.0 - decay) * self._rth * heat_w
        for total in (self._speed_sum, self._speed_sq_sum, self._tau_sq_sum):
            total[:] = 0.0
        self._tell()

    def state(self, time_s: float) -> FrictionState:
        """The estimate now, for comparing with a later one (`change_since`)."""
        coulomb, viscous = self.friction_nm()
        return FrictionState(float(time_s), tuple(coulomb.tolist()), tuple(viscous.tolist()))

    def warm_up(self, gear_rise_k: float) -> None:
        """A robot known to have run a while: gearboxes `gear_rise_k` above ambient."""
        self.rise_k = np.full(len(self.rise_k), float(gear_rise_k))
        self._tell()

    def reset(self) -> None:
        """A cold start: gearboxes at ambient."""
        self.rise_k = np.zeros(len(self.rise_k))
        self._cycles = 0
        for total in (self._speed_sum, self._speed_sq_sum, self._tau_sq_sum):
            total[:] = 0.0
        self._tell()


def change_since(before: FrictionState, now: FrictionState) -> FrictionChange:
    """The friction's change from `before` to `now`, with CHANGE_SPREAD of it as its uncertainty."""
    dc = np.subtract(now.coulomb_nm, before.coulomb_nm)
    dv = np.subtract(now.viscous_nm_s, before.viscous_nm_s)
    return FrictionChange(tuple(dc.tolist()), tuple(dv.tolist()), tuple((CHANGE_SPREAD * np.abs(dc)).tolist()),
                          tuple((CHANGE_SPREAD * np.abs(dv)).tolist()))


def update_estimates(thermal: ThermalModel, winding: WindingTemperature | None, gear: GearFriction | None,
                     tau_nm: np.ndarray, qd_rad_s: np.ndarray | None) -> None:
    """One motion cycle of the estimates the motion layer keeps (the thermal load, the windings' rise, the
    gearboxes' sums) from the cycle's torque and speed: with all three and the kernels on, their model parts in
    one compiled call (estimate_kernels.cycle_update: each one's operations, as its own update does them);
    else each one's own update (their numpy code the reference)."""
    kernels = thermal.kernels
    if compiled.ON and kernels is not None and winding is not None and gear is not None and qd_rad_s is not None:
        kernels.cycle_update(tau_nm, qd_rad_s, *thermal.kernel_state(), *winding.kernel_state(), *gear.kernel_state())
        winding.measure()
        gear.count(winding.rise_k)
        return
    thermal.update(tau_nm)
    if winding is not None:
        winding.update(tau_nm)
    if gear is not None and qd_rad_s is not None:
        gear.update(tau_nm, qd_rad_s, None if winding is None else winding.rise_k)
