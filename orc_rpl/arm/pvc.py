"""The arm-control room's path velocity controller: torque-limited path following by scaling time on-line."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from orc_rpl.errors import UsageError
from orc_rpl.plant import compiled

#: f(x, order): the joint path (order 0), its first and second derivatives by the path parameter x.
PathFunction = Callable[[Any, int], np.ndarray]
#: (q, dq/dx, d2q/dx2, dx/dt) -> (b1, b2) with tau = b1 * d2x/dt2 + b2: the arm controller as the
#: backend's model sees it (rigid-body dynamics, nominal friction, the servo's integral).
PathDynamics = Callable[[np.ndarray, np.ndarray, np.ndarray, float], tuple[np.ndarray, np.ndarray]]
#: (q, dq/dx, d2q/dx2, dx/dt as rows) -> row i -> (b1, b2): the same at many points of the path, computed in batches.
PathDynamicsRows = Callable[[np.ndarray, np.ndarray, np.ndarray, np.ndarray], Callable[[int], tuple[np.ndarray, np.ndarray]]]
#: x (1-D) -> (f(x), f'(x), f''(x)): the path and its two derivatives at many points at once.
PathOrders = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]

#: Back in step with the nominal trajectory when this close to it (path parameter, rad; its speed, rad/s).
RESYNC_X, RESYNC_SD = 1e-7, 1e-5
#: The least deceleration (rad/s^2 of the path parameter) of the braking profile that finishes a late path.
STOP_DECEL_MIN = 0.1
#: Share of the admissible deceleration a late command plans to stop at the path's end with.
BRAKE_SHARE = 0.8


@dataclass(frozen=True, slots=True)
class PvcSettings:
    """Tuning of the path velocity controller (the same for every robot; docs/motion.md)."""

    torque_share: float = 0.95      #: of tau_max the path acceleration may use; the rest is the servo's feedback
    overspeed: float = 0.03         #: path speed allowed above the nominal one at the same path point, to catch up
    catch_up_rad_s: float = 6.0     #: bandwidth of the time-correction term (kv = 2 w, kp = w^2)

    def __post_init__(self) -> None:
        if not (0.0 < self.torque_share <= 1.0 and 0.0 <= self.overspeed <= 0.2 and self.catch_up_rad_s > 0.0):
            raise UsageError("path velocity controller: torque_share in (0, 1], overspeed in [0, 0.2], catch_up > 0")


class PathVelocityController:
    """Follows one nominal trajectory x(t) on its path, slowing down where the torques would not suffice.

    The nominal trajectory is given per servo step (x, dx/dt); each motion cycle `cycle(k)` either
    returns None (the nominal rows are feasible and the controller is in step with them: use them
    unchanged, sample for sample) or the (q, qd, qdd) rows it commands instead. Out of step, the path
    acceleration is s'' = s''_n + kv (s'_n - s') + kp (s_n - s) (the time correction), saturated to the
    range the torque limits allow, with s' at most (1 + overspeed) times the nominal speed at the same
    path point; the references stay on the path f(s) whatever the time scale does.
    """

    #: the rows' (b1, model's b2, servo's integral) and the compiled range of their sum, where both are there
    _parts: Any = None
    _range_sum: Any = None

    def __init__(self, path: PathFunction, x_f: np.ndarray, sd_f: np.ndarray, sub: int, servo_period_s: float,
                 dynamics: PathDynamics, tau_max: np.ndarray, settings: PvcSettings = PvcSettings(),
                 dynamics_rows: PathDynamicsRows | None = None, path_orders: PathOrders | None = None) -> None:
        """`dynamics_rows`: the same dynamics for many path points at once; `path_orders`: the path's three orders
        at once (both optional, faster, the same numbers)."""
        self.path, self.sub, self.h = path, sub, servo_period_s
        self._orders: PathOrders = path_orders or (lambda x: (path(x, 0), path(x, 1), path(x, 2)))
        self.x_f, self.sd_f = x_f, sd_f
        self._sdd_f = np.append(np.diff(sd_f) / servo_period_s, 0.0)   #: nominal s'' over row i -> i+1
        self.dynamics = dynamics
        self.limit = np.asarray(tau_max, dtype=float) * settings.torque_share
        self._minus_limit = -self.limit
        self.settings = settings
        w = settings.catch_up_rad_s
        self._kp, self._kv = w * w, 2.0 * w
        rising = np.concatenate([[True], np.diff(x_f) > 0.0])
        self._x_mono, self._sd_mono = x_f[rising], sd_f[rising]
        self._t_mono = np.nonzero(rising)[0] * servo_period_s
        self.last_row = len(x_f) - 1
        self.end_x = float(x_f[-1])
        # the path at the nominal trajectory's motion-cycle rows, evaluated once: the in-step check of
        # every cycle then costs the model's torques only
        cycle_rows = np.arange(0, self.last_row + 1, sub)
        self._q_rows, self._d1_rows, self._d2_rows = self._orders(x_f[cycle_rows])
        self._at_cycle = None if dynamics_rows is None else dynamics_rows(self._q_rows, self._d1_rows, self._d2_rows,
                                                                          sd_f[cycle_rows])
        # what the in-step check of cycle k reads, as Python numbers (index k): the path parameter and its speed at
        # the cycle's end, the least and the largest nominal s'' of its first and last step
        self._x_rows, self._sd_rows = x_f[cycle_rows].tolist(), sd_f[cycle_rows].tolist()
        ends = self.last_row // sub * sub
        first, last = self._sdd_f[0:ends:sub], self._sdd_f[sub - 1:ends:sub]
        self._sdd_low = [0.0, *np.minimum(first, last).tolist()]
        self._sdd_high = [0.0, *np.maximum(first, last).tolist()]
        self.x, self.sd = float(x_f[0]), float(sd_f[0])   #: the commanded path parameter and speed
        self.in_sync = True
        self.done = False
        self.scaled_cycles = 0       #: cycles in which the time scale was changed (saturation avoided)
        self.cycles = 0
        kernels = compiled.kernels("orc_rpl.arm.pvc_kernels")   # numba's import only where a controller runs
        self._range: Any = None if kernels is None else kernels.admissible_range   #: the compiled range from b1, b2
        # the rows' b2 in two terms (`parts(i)`: the model's, the servo's integral), summed inside the compiled range
        self._parts: Any = None if kernels is None else getattr(self._at_cycle, "parts", None)
        self._range_sum: Any = None if kernels is None else kernels.admissible_range_sum
        self._kernels: Any = kernels   #: the compiled time-scaled cycle (scaled_profile, path_rates), None without

    # -- what the motion layer reads ----------------------------------------------------

    def lag_s(self) -> float:
        """How far behind the nominal trajectory the command is (s): the end comes this much later."""
        if self.in_sync:
            return 0.0
        t_nominal = float(np.interp(self.x, self._x_mono, self._t_mono))
        return self.cycles * self.sub * self.h - t_nominal

    def admissible(self, x: float, sd: float, cycle: int | None = None) -> tuple[float, float]:
        """The range of s'' the torque limits allow at (x, sd) (lo > hi when none does); at the nominal
        trajectory's motion-cycle row `cycle` when given (x is then that row's)."""
        if cycle is None:
            q, d1, d2 = self._orders(np.array([x]))
            b1, b2 = self.dynamics(q[0], d1[0], d2[0], sd)
        elif self._at_cycle is not None:
            if self._parts is not None and compiled.ON:
                return self._range_sum(*self._parts(cycle), self.limit)  # type: ignore[no-any-return]
            b1, b2 = self._at_cycle(cycle)
        else:
            b1, b2 = self.dynamics(self._q_rows[cycle], self._d1_rows[cycle], self._d2_rows[cycle], sd)
        if compiled.ON and self._range is not None:  # the compiled range (the numpy code below is its reference)
            return self._range(b1, b2, self.limit)  # type: ignore[no-any-return]
        limit, minus_limit = self.limit, self._minus_limit
        acting = np.abs(b1) >= 1e-9  # a joint the path acceleration does not move sets no bound
        if False in acting.tolist():
            b1, b2, limit, minus_limit = b1[acting], b2[acting], limit[acting], minus_limit[acting]
        # per joint, the s'' that reach -limit and +limit; the range is their intersection (one ufunc
        # each for all joints: this runs every motion cycle; fmin/fmax, as min/max, exact)
        r1, r2 = np.subtract(minus_limit, b2), np.subtract(limit, b2)
        np.divide(r1, b1, r1)
        np.divide(r2, b1, r2)
        lo = float(np.fmax.reduce(np.fmin(r1, r2), initial=-math.inf))
        hi = float(np.fmin.reduce(np.fmax(r1, r2), initial=math.inf))
        return lo, hi

    # -- the motion cycle ---------------------------------------------------------------

    def cycle(self, k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """Motion cycle k (1, 2, ...) of the trajectory: None to command the nominal rows, else the rows."""
        self.cycles = k
        end_row = k * self.sub
        if self.in_sync and end_row <= self.last_row:
            # in step when the nominal s'' of the cycle's steps (from its first to its last) is admissible
            x, sd = self._x_rows[k], self._sd_rows[k]
            lo, hi = self.admissible(x, sd, k)
            if lo <= self._sdd_low[k] and self._sdd_high[k] <= hi:
                self.x, self.sd = x, sd
                self.done = end_row == self.last_row
                return None
            self.in_sync = False
        return self._scaled(min(end_row, self.last_row), end_row > self.last_row)

    def _scaled(self, row: int, nominal_ended: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        x, sd, t_cycle = self.x, self.sd, self.sub * self.h
        x_n, sd_n = (self.end_x, 0.0) if nominal_ended else (float(self.x_f[row]), float(self.sd_f[row]))
        sdd_n = 0.0 if nominal_ended else float(self._sdd_f[row - 1])
        lo, hi = self.admissible(x, sd)
        kernels = self._kernels
        if compiled.ON and kernels is not None:  # the compiled profile and rates (the Python below is their reference)
            xs, sds = np.empty(self.sub), np.empty(self.sub)
            sdd, changed = kernels.scaled_profile(x, sd, t_cycle, x_n, sd_n, sdd_n, lo, hi, self.end_x, nominal_ended,
                                                  self._kv, self._kp, self.settings.overspeed, self._x_mono,
                                                  self._sd_mono, self.h, STOP_DECEL_MIN, BRAKE_SHARE, xs, sds)
        else:
            sdd, changed, xs, sds = self._profile(x, sd, t_cycle, x_n, sd_n, sdd_n, lo, hi, nominal_ended)
        if changed:
            self.scaled_cycles += 1
        x_end, sd_end = float(xs[-1]), float(sds[-1])
        if self.end_x - x_end < RESYNC_X and (nominal_ended or sd_end < RESYNC_SD):
            xs[-1], sds[-1], x_end, sd_end = self.end_x, 0.0, self.end_x, 0.0
            self.done = True
        self.x, self.sd = x_end, sd_end
        if not nominal_ended and abs(x_end - x_n) < RESYNC_X and abs(sd_end - sd_n) < RESYNC_SD:
            self.in_sync, self.x, self.sd = True, x_n, sd_n  # back in step: the nominal rows from the next cycle
        q, d1, d2 = self._orders(xs)
        if compiled.ON and kernels is not None:
            qd, qdd = np.empty(d1.shape), np.empty(d1.shape)
            kernels.path_rates(d1, d2, sds, sdd, qd, qdd)
        else:
            qdd = d2 * (sds * sds)[:, None] + d1 * np.where(sds > 0.0, sdd, 0.0)[:, None]
            qd = d1 * sds[:, None]
        if self.done:
            qd[-1], qdd[-1] = 0.0, 0.0
        return q, qd, qdd

    def _profile(self, x: float, sd: float, t_cycle: float, x_n: float, sd_n: float, sdd_n: float, lo: float,
                 hi: float, nominal_ended: bool) -> tuple[float, bool, np.ndarray, np.ndarray]:
        """The cycle's s'' from the admissible range [lo, hi], whether it differs from the wanted one, and the path
        parameter and its speed at the cycle's servo steps (the reference of pvc_kernels.scaled_profile)."""
        remaining = self.end_x - x
        braking = False
        if nominal_ended:  # the rest of the path: up to a braking profile at half the admissible deceleration
            a_stop = 0.5 * max(-lo, STOP_DECEL_MIN)
            braking = sd * sd >= 2.0 * a_stop * remaining
            # braking: the constant deceleration that stops exactly at the end (the path's end is kept)
            wanted = -sd * sd / (2.0 * remaining) if braking else (math.sqrt(2.0 * a_stop * remaining) - sd) / t_cycle
        else:  # the time correction
            wanted = sdd_n + self._kv * (sd_n - sd) + self._kp * (x_n - x)
            # and never slower than the nominal was at the same path point: a late command that tracked
            # the nominal in time would brake with it and stall short of the end (then start again)
            x_ahead = min(x + sd * t_cycle, self.end_x)
            wanted = max(wanted, (float(np.interp(x_ahead, self._x_mono, self._sd_mono)) - sd) / t_cycle)
        sdd = wanted if braking else min(max(wanted, lo), hi) if lo <= hi else 0.5 * (lo + hi)
        changed = sdd != wanted
        # never faster than (1 + overspeed) times the nominal speed where the cycle ends: keeps the
        # speed and acceleration limits the nominal profile respects, and stops at the path's end
        x_next = min(x + sd * t_cycle + 0.5 * sdd * t_cycle * t_cycle, self.end_x)
        if braking or nominal_ended and x_next >= self.end_x:
            bound = math.inf  # the braking profile, or the path ends inside this cycle
        elif nominal_ended:
            bound = math.sqrt(2.0 * a_stop * (self.end_x - x_next))
        else:
            bound = (1.0 + self.settings.overspeed) * float(np.interp(x_next, self._x_mono, self._sd_mono))
            # and slow enough to stop at the end with the deceleration the torques allow here (with a margin):
            # the nominal brakes harder than a heavier or colder arm can
            bound = min(bound, math.sqrt(2.0 * BRAKE_SHARE * max(-lo, STOP_DECEL_MIN) * (self.end_x - x_next)))
        if sd + sdd * t_cycle > bound:
            sdd = (bound - sd) / t_cycle
        if sd + sdd * t_cycle <= 0.0 and x_next < self.end_x:
            # the torques cannot even hold the arm here (the model's own limit): go on along the path at
            # the wanted rate and let the servo saturate, rather than stand still or back up
            sdd = min(max(wanted, STOP_DECEL_MIN), bound / t_cycle) if sd <= 0.0 else -sd / t_cycle
        taus = np.arange(1, self.sub + 1) * self.h
        if sdd < 0.0:  # at rest from where the speed reaches zero inside the cycle
            taus = np.minimum(taus, sd / -sdd)
        xs = np.minimum(x + sd * taus + 0.5 * sdd * taus * taus, self.end_x)
        sds = np.maximum(sd + sdd * taus, 0.0)
        return sdd, changed, xs, sds
