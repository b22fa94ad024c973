"""Short motions (ShortMove, thesis 5.2): jerk-limited single-target trajectories with ruckig, dynamics taken as constant."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from orc_rpl.errors import PlanningError
from orc_rpl.motion.paths import DensePath
from orc_rpl.motion.trajectory import SplinePath, Trajectory

#: jerk limit as a multiple of the acceleration limit (1/s) when the caller gives none
DEFAULT_JERK_PER_S = 40.0


@dataclass(frozen=True, slots=True)
class ShortLimits:
    """Per-joint limits of a short move, already reduced for the (constant) dynamics at the start."""

    qd_max: np.ndarray
    qdd_max: np.ndarray
    qddd_max: np.ndarray


def constant_dynamics_accel(
    qdd_max: np.ndarray, tau_max: np.ndarray, gravity_nm: np.ndarray, inertia_diag: np.ndarray
) -> np.ndarray:
    """Acceleration limits the torque allows at one configuration: (tau_max - |gravity|) / M_ii."""
    spare = np.maximum(tau_max - np.abs(gravity_nm), 0.05 * tau_max)
    return np.minimum(qdd_max, spare / np.maximum(inertia_diag, 1e-9))


def _ruckig(q0: np.ndarray, qd0: np.ndarray, qdd0: np.ndarray, q1: np.ndarray, lim: ShortLimits):  # type: ignore[no-untyped-def]
    """One single-target ruckig calculation (never intermediate waypoints: the Community wheel sends them away)."""
    from ruckig import InputParameter, Result, Ruckig
    from ruckig import Trajectory as RuckigTrajectory

    n = len(q0)
    inp = InputParameter(n)
    inp.current_position = q0.tolist()
    inp.current_velocity = qd0.tolist()
    inp.current_acceleration = qdd0.tolist()
    inp.target_position = q1.tolist()
    inp.target_velocity = [0.0] * n
    inp.target_acceleration = [0.0] * n
    inp.max_velocity = lim.qd_max.tolist()
    inp.max_acceleration = lim.qdd_max.tolist()
    inp.max_jerk = lim.qddd_max.tolist()
    traj = RuckigTrajectory(n)
    try:
        result = Ruckig(n).calculate(inp, traj)
    except RuntimeError as exc:  # ruckig throws on invalid input (limits, NaN)
        raise PlanningError(f"short move: ruckig refused the input ({exc})") from exc
    ok = result in (Result.Working, Result.Finished)
    return traj if ok else int(result)


def short_trajectory(
    q0: np.ndarray,
    qd0: np.ndarray,
    qdd0: np.ndarray,
    q1: np.ndarray,
    lim: ShortLimits,
    dt_s: float,
    sub: int,
    owner: int,
    tcp_of: Callable[[np.ndarray], np.ndarray],
    tcp_speed_max_m_s: float | None = None,
) -> Trajectory:
    """A short move sampled every dt_s, its TCP kept under `tcp_speed_max_m_s`; ruckig's -110 retried softer."""
    if tcp_speed_max_m_s is not None and not np.any(qd0) and not np.any(qdd0):
        lim = _capped(q0, q1, lim, tcp_of, tcp_speed_max_m_s)
    traj = _ruckig(q0, qd0, qdd0, q1, lim)
    tries = 0
    while isinstance(traj, int):
        if traj != -110 or tries >= 3:
            raise PlanningError(f"short move: ruckig could not compute a trajectory (result {traj})")
        # -110: the time-synchronisation failed numerically; a slightly different jerk limit avoids the corner case
        tries += 1
        lim = ShortLimits(lim.qd_max, lim.qdd_max, lim.qddd_max * (0.7**tries))
        traj = _ruckig(q0, qd0, qdd0, q1, lim)
    duration = float(traj.duration)
    cycles = max(1, math.ceil(duration / dt_s - 1e-9))
    t = np.minimum(np.arange(cycles * sub + 1) * (dt_s / sub), duration)
    q = np.empty((len(t), len(q0)))
    qd = np.empty_like(q)
    qdd = np.empty_like(q)
    for i, ti in enumerate(t):
        p, v, a = traj.at_time(float(ti))
        q[i], qd[i], qdd[i] = p, v, a
    q[t >= duration], qd[t >= duration], qdd[t >= duration] = q1, 0.0, 0.0
    # The path of a short move is taken as the joint-space line from start to target (ruckig's
    # time-synchronised profile stays close to it); s is the progress along that line.
    chord = q1 - q0
    length2 = float(chord @ chord)
    s = np.clip(((q - q0) @ chord) / length2, 0.0, 1.0) if length2 > 0 else np.linspace(0.0, 1.0, len(q))
    s[-1] = 1.0
    ends = np.stack([q0, q1])
    path = SplinePath(DensePath(ends, np.stack([tcp_of(q0), tcp_of(q1)]), np.full(2, owner), np.array([0.0, 1.0])))
    sd = np.linalg.norm(qd, axis=1)
    return Trajectory(
        dt_s, sub, path, s * path.length, sd, q, qd, qdd, np.full(cycles + 1, owner), s[::sub], duration, blendable=False, kind="short"
    )


def _capped(q0: np.ndarray, q1: np.ndarray, lim: ShortLimits, tcp_of: Callable[[np.ndarray], np.ndarray],
            cap_m_s: float) -> ShortLimits:
    """Limits whose rest-to-rest trajectory keeps the TCP under the cap (manual mode: 250 mm/s).

    ruckig limits joints only. A rest-to-rest profile slowed uniformly in time by a factor r keeps its
    path and scales velocity by r, acceleration by r^2 and jerk by r^3, so the TCP's peak speed measured
    on the unscaled profile gives the exact factor.
    """
    traj = _ruckig(q0, np.zeros_like(q0), np.zeros_like(q0), q1, lim)
    if isinstance(traj, int):
        return lim  # the caller reports the failure
    duration = float(traj.duration)
    if duration <= 0.0:
        return lim
    t = np.linspace(0.0, duration, max(8, math.ceil(duration / 0.001)) + 1)
    tcp = np.array([tcp_of(np.asarray(traj.at_time(float(ti))[0])) for ti in t])
    peak_m_s = float(np.max(np.linalg.norm(np.diff(tcp, axis=0), axis=1) / np.diff(t)))
    if peak_m_s <= cap_m_s:
        return lim
    r = 0.98 * cap_m_s / peak_m_s  # 2 % for the chords between samples
    return ShortLimits(lim.qd_max * r, lim.qdd_max * r * r, lim.qddd_max * r**3)


def stop_trajectory(
    q0: np.ndarray, qd0: np.ndarray, qdd0: np.ndarray, lim: ShortLimits, dt_s: float, sub: int, template: Trajectory
) -> Trajectory:
    """Bring a short move to rest as fast as the jerk and acceleration limits allow (ruckig's velocity interface)."""
    from ruckig import ControlInterface, InputParameter, Result, Ruckig
    from ruckig import Trajectory as RuckigTrajectory

    n = len(q0)
    inp = InputParameter(n)
    inp.control_interface = ControlInterface.Velocity
    inp.current_position, inp.current_velocity, inp.current_acceleration = q0.tolist(), qd0.tolist(), qdd0.tolist()
    inp.target_velocity, inp.target_acceleration = [0.0] * n, [0.0] * n
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = lim.qd_max.tolist(), lim.qdd_max.tolist(), lim.qddd_max.tolist()
    traj = RuckigTrajectory(n)
    if Ruckig(n).calculate(inp, traj) not in (Result.Working, Result.Finished):
        raise PlanningError("short move: ruckig could not compute the stop")
    duration = float(traj.duration)
    cycles = max(1, math.ceil(duration / dt_s - 1e-9))
    t = np.minimum(np.arange(cycles * sub + 1) * (dt_s / sub), duration)
    rows = [traj.at_time(float(ti)) for ti in t]
    q = np.array([r[0] for r in rows])
    qd = np.array([r[1] for r in rows])
    qdd = np.array([r[2] for r in rows])
    qd[t >= duration], qdd[t >= duration] = 0.0, 0.0
    path = template.path
    chord = path.dense.q[-1] - path.dense.q[0]
    length2 = float(chord @ chord)
    s = np.clip(((q - path.dense.q[0]) @ chord) / length2, 0.0, 1.0) if length2 > 0 else np.ones(len(q))
    owner = np.full(cycles + 1, template.owner[-1])
    return Trajectory(dt_s, sub, path, s * path.length, np.zeros(len(q)), q, qd, qdd, owner, s[::sub], duration, blendable=False, kind="brake")
