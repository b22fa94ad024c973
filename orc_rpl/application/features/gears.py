"""What the applications need to know of a robot's elastic gears: their lowest anti-resonance at a pose, its period."""

from __future__ import annotations

import math
from typing import Any

import numpy as np


def lowest_anti_resonance_rad_s(robot: Any, q: Any) -> float | None:
    """The lowest of the joints' anti-resonances sqrt(k / J_link) at joint angles q (rad/s), J_link being the
    model's inertia of each joint less its rotor's: the frequency above which a link no longer follows its motor.
    None on rigid gears (a robot whose servo names no gears: `servo_gains().gear_stiffness_nm_rad` empty)."""
    gains = getattr(robot, "servo_gains", lambda: None)()
    stiffness = np.array(getattr(gains, "gear_stiffness_nm_rad", ()) or (), dtype=float)
    q = np.asarray(q, dtype=float)
    if not len(stiffness) or len(stiffness) != len(q):
        return None
    rotor = np.array(gains.rotor_inertia_kg_m2 or np.zeros(len(q)), dtype=float)
    zero = tuple(np.zeros(len(q)))
    weight = np.array(robot.inverse_dynamics(tuple(q), zero, zero, 0.0))
    inertia = np.array([robot.inverse_dynamics(tuple(q), zero, tuple(unit), 0.0)[i] - weight[i]
                        for i, unit in enumerate(np.eye(len(q)))])
    return float(np.min(np.sqrt(stiffness / np.maximum(inertia - rotor, 1e-9))))


def gear_period_cycles(robot: Any, q: Any) -> int:
    """Motion cycles in one period of the gears' lowest anti-resonance at pose q; 1 on rigid gears."""
    lowest_rad_s = lowest_anti_resonance_rad_s(robot, q)
    return 1 if lowest_rad_s is None else max(1, round(2.0 * math.pi / lowest_rad_s / robot.dt_s))


def start_averaging_s(robot: Any) -> float:
    """How long the robot's motion layer averages the start of a move from rest over its gears' periods (s; 0 on
    rigid gears, or a robot that does not say): a move reaches its accelerations that much later."""
    own = getattr(robot, "start_averaging_s", None)
    return float(own()) if own is not None else 0.0
