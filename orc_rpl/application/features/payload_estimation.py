"""Payload identification from a short recording of joint torques (IDENTMOVE): the estimate, its spread, the answer's confidence.

The robot model gives the torques without a load, tau_0(q, qd, qdd), and the torques a 1 kg load at the
flange adds, d = tau_1 - tau_0. Per joint j and window w of the recording the measured torque is

    tau_j = tau_0j + m d_j + c_j + b_j qd_j + noise

with the payload m shared by every joint and, per joint, an offset c_j (Coulomb friction while the joint
turns one way, and a constant error of the model) and a viscous friction b_j. Windows, not samples: over a
window of WINDOW samples the torque is averaged and the acceleration is the change of the measured velocity
divided by the window's length, so no differentiated velocity (whose one sample at an acceleration switch
used to dominate the fit) enters; a joint whose measured speed is noisy takes the window's acceleration from
its encoder angles instead (a quadratic through them), and the switch test allows for the speed's noise. The offsets and frictions have a prior (zero mean, OFFSET_PRIOR_NM and
VISCOUS_PRIOR_NM_S spread): what the recording cannot separate from the payload (a constant offset against a
load's nearly constant weight) stays uncertain instead of being guessed. Each joint's equations are
weighted by its noise, estimated from the residuals of a first fit (and never below NOISE_FLOOR_NM), and the
estimate's standard deviation comes from the posterior covariance.

`confidence(answer_of, m, sigma)` asks the user's classification at the estimate and around it: the answer
is trusted when it is the same from m - 3 sigma to m + 3 sigma; its confidence is the normal probability
mass over the grid points that give the same answer.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from orc_rpl.motion.gear_friction import SIGN_SMOOTH_RAD_S
from orc_rpl.robot.friction import friction_torque_nm

#: Samples averaged into one window (4 ms motion cycle: 20 ms windows).
WINDOW = 5
#: A window whose per-cycle joint accelerations spread by more than this (rad/s^2, plus a tenth of their size)
#: holds an acceleration switch and is left out.
SWITCH_RAD_S2 = 0.3
#: ... or more than this many times the median spread of the recording's windows (the measured speed's noise).
NOISE_SPREADS = 2.5
#: Prior spread of each joint's offset (N m): Coulomb friction and a constant model error together.
OFFSET_PRIOR_NM = 0.3
#: Prior spread of each joint's viscous friction (N m s/rad).
VISCOUS_PRIOR_NM_S = 0.5
#: Each joint's torque noise is at least this (N m): a fit cannot be more certain than the motor's resolution.
NOISE_FLOOR_NM = 0.2
#: The answer must hold over the estimate +- this many standard deviations.
SIGMAS = 3.0
#: A joint whose measured speed is noisier than this (rad/s: the median size of its second difference, which a
#: smooth motion keeps near zero) takes its accelerations from its angles (a quadratic fit over each window).
SPEED_NOISE_RAD_S = 1.5e-4
#: Grid of the confidence (in standard deviations from the estimate).
GRID = np.arange(-4.0, 4.0001, 0.25)


@dataclass(frozen=True, slots=True)
class PayloadEstimate:
    """The payload (kg) and its standard deviation (kg); `windows` used."""

    mass_kg: float
    sigma_kg: float
    windows: int


def estimate(samples: Sequence[Any], inverse_dynamics: Callable[..., Sequence[float]],
             tare: Sequence[Any] | None = None, friction_change: Any = None, window: int = WINDOW) -> PayloadEstimate:
    """The payload from samples (time_s, q, qd, torque) and the controller's model `inverse_dynamics(q, qd, qdd, kg)`.

    With `tare` (the same lift recorded holding nothing), window k of the tare is taken off window k of the
    recording: what the model gets wrong along the path (friction, masses it does not know) cancels, and the
    payload is fitted to what is left; a window clean in only one of the two is left out.

    `friction_change` (with a tare: the controller's estimate of how the joint friction changed since the tare,
    motion.gear_friction.FrictionChange): its torque, Coulomb dc tanh(qd / SIGN_SMOOTH_RAD_S) + viscous dv qd,
    is taken off too, and its uncertainty widens the offset's and the viscous friction's priors. `window`: samples
    averaged into one window (WINDOW; on elastic gears a period of their lowest anti-resonance: `identify_window`)."""
    if tare is None:
        rows = _windows(samples, window_size=window)
        reference = None
    else:
        both = [(a, b) for a, b in zip(_windows(samples, True, window), _windows(tare, True, window))
                if a is not None and b is not None]
        rows, reference = [a for a, _ in both], [b for _, b in both]
    if not rows:
        return PayloadEstimate(0.0, math.inf, 0)
    n = len(rows[0][0])
    tau0 = np.array([inverse_dynamics(q, qd, qdd, 0.0) for q, qd, qdd, _ in rows], dtype=float)
    d = np.array([inverse_dynamics(q, qd, qdd, 1.0) for q, qd, qdd, _ in rows], dtype=float) - tau0
    tau = np.array([t for _, _, _, t in rows], dtype=float)
    qd = np.array([v for _, v, _, _ in rows], dtype=float)
    y = tau - tau0                                           # (windows, joints)
    if reference is not None:
        y = y - np.array([t - np.asarray(inverse_dynamics(q, v, a, 0.0), dtype=float) for q, v, a, t in reference])
    offset_var, viscous_var = np.full(n, OFFSET_PRIOR_NM ** 2), np.full(n, VISCOUS_PRIOR_NM_S ** 2)
    if reference is not None and friction_change is not None:  # the gearboxes warmed since the tare
        dc, dv = np.array(friction_change.coulomb_nm), np.array(friction_change.viscous_nm_s)
        y = y - friction_torque_nm(dc, dv, qd, SIGN_SMOOTH_RAD_S)
        offset_var = offset_var + np.square(friction_change.coulomb_sigma_nm)
        viscous_var = viscous_var + np.square(friction_change.viscous_sigma_nm_s)
    k = len(rows)
    # unknowns: m, c_1..c_n, b_1..b_n; equation (w, j): y = m d + c_j + b_j qd_j
    a = np.zeros((k * n, 1 + 2 * n))
    for j in range(n):
        a[j::n, 0] = d[:, j]
        a[j::n, 1 + j] = 1.0
        a[j::n, 1 + n + j] = qd[:, j]
    b = y.reshape(-1)
    prior = np.concatenate(([0.0], 1.0 / offset_var, 1.0 / viscous_var))
    noise = np.full(n, 1.0)
    for _ in range(2):  # a first fit with unit noise, then each joint weighted by its residual noise
        w = np.tile(1.0 / noise ** 2, k)
        info = a.T @ (a * w[:, None]) + np.diag(prior)
        theta = np.linalg.solve(info, a.T @ (w * b))
        residual = (b - a @ theta).reshape(k, n)
        dof = max(1.0, k - 2.0)  # each joint spends about two windows on its offset and friction
        noise = np.maximum(NOISE_FLOOR_NM, np.sqrt((residual ** 2).sum(axis=0) / dof))
    w = np.tile(1.0 / noise ** 2, k)
    info = a.T @ (a * w[:, None]) + np.diag(prior)
    theta = np.linalg.solve(info, a.T @ (w * b))
    covariance = np.linalg.inv(info)
    return PayloadEstimate(float(theta[0]), float(math.sqrt(max(covariance[0, 0], 0.0))), k)


def _windows(samples: Sequence[Any], keep: bool = False, window_size: int = WINDOW) -> list[Any]:
    """(q, qd, qdd, mean torque) per clean window: q at its middle, qd its mean, qdd the velocity change across it
    over its length, against the torque between the samples (the mean of each cycle's two ends: the motor
    torque is sampled at the cycle's boundaries, the velocity changes in between). A window in which the
    acceleration switches (its per-cycle accelerations spread by more than SWITCH_RAD_S2, or NOISE_SPREADS times
    the recording's median spread, plus a tenth of their size) is left out: there the servo's torque and the
    measured motion do not average alike (with `keep`, it is None in its place, so two recordings' windows stay
    paired by index). A joint whose measured speed is noisy (SPEED_NOISE_RAD_S) takes qdd from its angles."""
    spans = []
    for start in range(0, len(samples) - window_size, window_size):
        window = samples[start: start + window_size + 1]
        t = np.array([s.time_s for s in window])
        if np.any(np.diff(t) <= 0):
            spans.append((window, t, None, None))
            continue
        qd = np.array([s.qd for s in window], dtype=float)
        per_cycle = np.diff(qd, axis=0) / np.diff(t)[:, None]
        spans.append((window, t, qd, per_cycle))
    spreads = [pc.max(axis=0) - pc.min(axis=0) for _, _, _, pc in spans if pc is not None]
    # a measured speed's noise spreads the per-cycle accelerations of every window alike: a switch stands out of that
    floor = np.maximum(SWITCH_RAD_S2, NOISE_SPREADS * np.median(spreads, axis=0)) if spreads else SWITCH_RAD_S2
    speeds = np.array([s.qd for s in samples], dtype=float)
    noisy = (np.median(np.abs(np.diff(speeds, 2, axis=0)), axis=0) > SPEED_NOISE_RAD_S) if len(samples) > 2 else None
    out = []
    for window, t, qd, per_cycle in spans:
        if per_cycle is None:
            if keep:
                out.append(None)
            continue
        spread = per_cycle.max(axis=0) - per_cycle.min(axis=0)
        if np.any(spread > floor + 0.1 * np.abs(per_cycle).max(axis=0)):
            if keep:
                out.append(None)
            continue
        qdd_array = (qd[-1] - qd[0]) / (t[-1] - t[0])
        if noisy is not None and noisy.any():  # the encoder's angles are far finer than the noisy speed
            fit = np.polynomial.polynomial.polyfit(t - t.mean(), np.array([s.q for s in window], dtype=float), 2)
            qdd_array = np.where(noisy, 2.0 * fit[2], qdd_array)
        qdd = tuple(qdd_array.tolist())
        torques = np.array([s.torque for s in window], dtype=float)
        torque = (torques[1:] + torques[:-1]).mean(axis=0) / 2  # the trapezoid: the torque between the samples
        out.append((tuple(window[window_size // 2].q), tuple(qd.mean(axis=0).tolist()), qdd, torque))
    return out


def confidence(answer_of: Callable[[float], Any], mass_kg: float, sigma_kg: float) -> tuple[Any, float, bool]:
    """(the answer at the estimate, its confidence 0..1, trusted: the same answer over +- SIGMAS sigma)."""
    answer = answer_of(max(0.0, mass_kg))
    if not math.isfinite(sigma_kg):
        return answer, 0.0, False
    weights = np.exp(-0.5 * GRID ** 2)
    same = np.array([answer_of(max(0.0, mass_kg + g * sigma_kg)) == answer for g in GRID])
    trusted = bool(np.all(same[np.abs(GRID) <= SIGMAS + 1e-9]))
    return answer, float(weights[same].sum() / weights.sum()), trusted
