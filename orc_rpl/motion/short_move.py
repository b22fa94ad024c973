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
#: On elastic gears each joint of a short move from rest is averaged over these windows (s) in turn. After an
#: unaveraged ShortMove's reference ends the IRB 2400's links ring under the state feedback: j1 and j2 at about
#: 16 Hz, j3 at 24 Hz (the spot welds' moves: 7 to 15 mm/s at the TCP 40 to 120 ms after the end). A box over j3's
#: period (0.042 s) and one over half of j1's and j2's leave them at 3.3 to 3.8 mm/s (j1 moves that much at rest:
#: after a path move averaged over the whole anti-resonance periods, 3.5), each move about 0.07 s longer; the whole
#: anti-resonance periods the path moves take (0.164 + 0.131 s) cost 0.44 s a spot. docs/motion.md, "Averaging on
#: elastic gears".
ELASTIC_WINDOWS_S = (0.042, 0.032)


def short_windows(path_windows_s: tuple[float, ...]) -> tuple[float, ...]:
    """The averaging windows of a short move from rest on a layer whose path moves are averaged over
    `path_windows_s`: none on rigid gears (no windows), ELASTIC_WINDOWS_S on elastic ones."""
    return ELASTIC_WINDOWS_S if path_windows_s else ()


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
    windows_s: tuple[float, ...] = (),
) -> Trajectory:
    """A short move sampled every dt_s, its TCP kept under `tcp_speed_max_m_s`, each joint's profile averaged over
    `windows_s` in turn (`short_windows`); ruckig's -110 retried softer."""
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
    if windows_s:
        rows = len(q)
        q, qd, qdd = _box_averaged(q, qd, qdd, windows_s, dt_s / sub)
        duration += (len(q) - rows) * dt_s / sub   # each window adds its length less one step
        cycles = max(1, math.ceil((len(q) - 1) / sub))
        pad = cycles * sub + 1 - len(q)
        q = np.concatenate([q, np.tile(q1, (pad, 1))])
        qd, qdd = np.concatenate([qd, np.zeros((pad, len(q1)))]), np.concatenate([qdd, np.zeros((pad, len(q1)))])
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


def _box_averaged(q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, windows_s: tuple[float, ...], step_s: float
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each joint's samples (every step_s, from rest to rest) averaged over each window in turn.

    The joints' own profiles are averaged (a box average of q, q' and q'' alike keeps them consistent), not the
    progress along the chord: ruckig's joints are time-synchronised, not on the chord."""
    start, end, rest = q[0].copy(), q[-1].copy(), np.zeros(q.shape[1])
    for window_s in windows_s:
        n = max(1, int(round(window_s / step_s)))
        q, qd, qdd = _box(q, start, end, n), _box(qd, rest, rest, n), _box(qdd, rest, rest, n)
    q[-1], qd[-1], qdd[-1] = end, 0.0, 0.0   # the averages of the end's samples are the end up to rounding
    return q, qd, qdd


def _box(samples: np.ndarray, before: np.ndarray, after: np.ndarray, n: int) -> np.ndarray:
    """Each column's moving average over n samples, held at `before` and `after` outside (n - 1 rows longer)."""
    padded = np.concatenate([np.tile(before, (n - 1, 1)), samples, np.tile(after, (n - 1, 1))])
    sums = np.cumsum(np.concatenate([np.zeros((1, padded.shape[1])), padded]), axis=0)
    return (sums[n:] - sums[:-n]) / n


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
