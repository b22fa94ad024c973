"""Zone blending: replace the corner between two paths by a smooth joint-space curve inside the TCP zone."""

from __future__ import annotations

import math

import numpy as np

from orc_rpl.motion.kinematics import Kinematics
from orc_rpl.motion.paths import DensePath


def _unit(v: np.ndarray) -> np.ndarray:
    n = float(np.linalg.norm(v))
    return v / n if n > 1e-12 else v * 0.0


def _chord(path: DensePath) -> np.ndarray:
    """Cumulative joint-space chord length along a dense path."""
    return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(path.q, axis=0), axis=1))])


def entry_index(path: DensePath, zone_m: float, tail_chord_rad: float) -> int:
    """Where a path ending at a corner enters the zone: the last sample at least zone_m (TCP) from the end.

    The blend never takes more than the second half of the last segment (`tail_chord_rad` of joint
    chord before the corner), so two short segments with a large zone still keep their middles.
    """
    d = np.linalg.norm(path.tcp - path.tcp[-1], axis=1)
    outside = np.nonzero(d >= zone_m)[0]
    i = int(outside[-1]) if len(outside) else 0
    to_end = _chord(path)[-1] - _chord(path)
    half = np.nonzero(to_end <= 0.5 * tail_chord_rad + 1e-12)[0]
    return max(i, int(half[0]))


def exit_index(path: DensePath, zone_m: float, head_chord_rad: float) -> int:
    """Where a path starting at a corner leaves the zone, at most half-way along its first segment."""
    d = np.linalg.norm(path.tcp - path.tcp[0], axis=1)
    outside = np.nonzero(d >= zone_m)[0]
    i = int(outside[0]) if len(outside) else len(path) - 1
    half = np.nonzero(_chord(path) <= 0.5 * head_chord_rad + 1e-12)[0]
    return min(i, int(half[-1]))


def blend(
    kin: Kinematics,
    current: DensePath,
    nxt: DensePath,
    zone_m: float,
    earliest: int,
    tool: np.ndarray | None,
    tail_chord_rad: float,
    head_chord_rad: float,
) -> DensePath | None:
    """`current` (ending at the corner) joined to `nxt` through a blend; None when the zone is already passed.

    The corner is cut by a cubic Bezier curve in joint space whose end tangents follow both
    paths, so the joint path is C1 and the TCP stays near the corner. The first half of the
    curve belongs to the ending motion (its s reaches 1 at the middle), the second to the next.
    """
    if zone_m <= 0.0 or len(current) < 3 or len(nxt) < 3:
        return None
    i_a = entry_index(current, zone_m, tail_chord_rad)
    i_b = exit_index(nxt, zone_m, head_chord_rad)
    if i_a < earliest or i_a >= len(current) - 1 or i_b < 1:
        return None
    q_a, q_b = current.q[i_a], nxt.q[i_b]
    t_a = _unit(current.q[i_a + 1] - current.q[i_a - 1] if i_a > 0 else current.q[1] - current.q[0])
    t_b = _unit(nxt.q[min(i_b + 1, len(nxt) - 1)] - nxt.q[i_b - 1])
    chord = float(np.linalg.norm(q_b - q_a))
    if chord < 1e-9:
        return None
    ctrl = np.stack([q_a, q_a + t_a * chord / 3.0, q_b - t_b * chord / 3.0, q_b])
    m = int(min(81, max(9, math.ceil(chord / 0.01) + 1)))
    w = np.linspace(0.0, 1.0, m)[:, None]
    basis = np.hstack([(1 - w) ** 3, 3 * w * (1 - w) ** 2, 3 * w**2 * (1 - w), w**3])
    qs = basis @ ctrl
    first = w[:, 0] < 0.5
    owner = np.where(first, current.owner[-1], nxt.owner[0])
    if current.owner[-1] == nxt.owner[0]:  # a via point inside one move: its s runs on through the blend
        s = current.s[i_a] + (nxt.s[i_b] - current.s[i_a]) * w[:, 0]
    else:
        s = np.where(first, current.s[i_a] + (1.0 - current.s[i_a]) * w[:, 0] / 0.5, nxt.s[i_b] * (w[:, 0] - 0.5) / 0.5)
    curve = DensePath(qs, kin.tcp_positions(qs, tool), owner.astype(int), s)
    return current.cut(0, i_a).then(curve).then(nxt.cut(i_b))
