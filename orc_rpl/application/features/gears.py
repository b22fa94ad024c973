"""What the applications need to know of a robot's elastic gears: their lowest anti-resonance at a pose."""

from __future__ import annotations

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
