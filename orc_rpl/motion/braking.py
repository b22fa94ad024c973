"""StopMove: the quickest deceleration that keeps the robot on its path, within the joint acceleration limits."""

from __future__ import annotations

import math

import numpy as np

from orc_rpl.motion.trajectory import Trajectory


def _brake_accel(d1: np.ndarray, d2: np.ndarray, sd: float, qdd_max: np.ndarray) -> float:
    """The most negative path acceleration sdd with |q' sdd + q'' sd^2| <= qdd_max on every joint."""
    lo, hi = -math.inf, math.inf
    centrifugal = d2 * sd * sd
    for a, b, lim in zip(d1, centrifugal, qdd_max):
        if abs(a) < 1e-12:
            continue
        r1, r2 = (-lim - b) / a, (lim - b) / a
        lo, hi = max(lo, min(r1, r2)), min(hi, max(r1, r2))
    if lo == -math.inf:
        return -1e3
    # If the curvature term alone exceeds a limit the interval is empty: brake as hard as the bound allows.
    return lo if lo <= hi else 0.5 * (lo + hi)


def brake(traj: Trajectory, row: int, qdd_max: np.ndarray, x_sd: tuple[float, float] | None = None) -> Trajectory:
    """A trajectory that starts at fine row `row` of `traj` (or at path parameter and speed `x_sd`, where a
    time-scaled command really is) and stops on the same path as fast as allowed."""
    path = traj.path
    h = traj.dt_s / traj.sub
    x, sd = (float(traj.x_f[row]), float(traj.sd_f[row])) if x_sd is None else x_sd
    xs, sds, sdds = [x], [sd], [0.0]
    end = path.length
    while sd > 0.0 and x < end:
        d1, d2 = path(x, 1), path(x, 2)
        sdd = min(_brake_accel(d1, d2, sd, qdd_max), -1e-6)
        if sd + sdd * h <= 0.0:
            dt = -sd / sdd  # stop inside this step
            x = min(end, x + sd * dt + 0.5 * sdd * dt * dt)
            sd = 0.0
        else:
            x = min(end, x + sd * h + 0.5 * sdd * h * h)
            sd = sd + sdd * h
        xs.append(x)
        sds.append(sd)
        sdds.append(sdd)
    steps = len(xs) - 1
    cycles = max(1, math.ceil(steps / traj.sub))
    pad = cycles * traj.sub + 1 - len(xs)
    xs += [x] * pad
    sds += [0.0] * pad
    sdds += [0.0] * pad
    x_f, sd_f, sdd_f = np.array(xs), np.array(sds), np.array(sdds)
    d1, d2 = path(x_f, 1), path(x_f, 2)
    q_f = path(x_f)
    qd_f = d1 * sd_f[:, None]
    qdd_f = d2 * (sd_f**2)[:, None] + d1 * sdd_f[:, None]
    qd_f[-1], qdd_f[-1] = 0.0, 0.0
    owner, s = path.owner_and_s(x_f[:: traj.sub])
    return Trajectory(traj.dt_s, traj.sub, path, x_f, sd_f, q_f, qd_f, qdd_f, owner, s, steps * h, blendable=False, kind="brake")
