"""Elastic gears: how much of the averaging windows a trajectory from rest needs, from its steps' twist of the gears."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from orc_rpl.motion.trajectory import SplinePath

#: A step twisting a gear by this much (rad) or more gets the whole windows; a smaller one the same share of them.
#: bench_motion's and bench_arm_control's moves (elastic gears under state feedback) twist j1..j3's gears by
#: about 1 to 5 mrad at their steps; windows scaled so (at least LEAST_WINDOW_S), measured against the whole windows
#: (0.75 of the anti-resonance periods): see docs/motion.md, "On elastic gears".
FULL_STEP_RAD = 4e-3
#: No window shorter than this (s): a step in the path acceleration is a step in every gear's torque.
LEAST_WINDOW_S = 0.02
#: The largest steps of a profile's path acceleration whose twist is computed (the start, the switches, the end).
STEPS_CHECKED = 6


@dataclass(frozen=True)
class GearSteps:
    """The elastic gears a trajectory's path-acceleration steps twist, and the averaging windows that calls for.

    A step dx'' of the path acceleration is a step M(q) f'(x) dx'' of the joints' torques, the links' share of it
    (less the rotors' own inertia) a step of each gear's twist, that torque times the gear's compliance. Under the
    state feedback the rotor must carry that change of twist within the averaging: the windows scale with the
    largest step's twist, whole at `full_step_rad`, never shorter than `least_s`.
    """

    rotor_inertia_kg_m2: tuple[float, ...]
    compliance_rad_nm: tuple[float, ...]   #: 1 / the gear's stiffness; 0 for a joint whose twist does not count
    full_step_rad: float = FULL_STEP_RAD
    least_s: float = LEAST_WINDOW_S

    def largest_twist_rad(self, path: SplinePath, x_grid: np.ndarray, sd_grid: np.ndarray,
                          inverse_dynamics: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]) -> float:
        """The largest change of a gear's twist at a step of the profile's path acceleration (the profile from rest:
        constant acceleration between grid points, from and to rest at its ends); `inverse_dynamics` the planner's
        (its payload included)."""
        acc = (sd_grid[1:] ** 2 - sd_grid[:-1] ** 2) / (2.0 * np.maximum(np.diff(x_grid), 1e-15))
        jumps = np.diff(np.concatenate([[0.0], acc, [0.0]]))   # at each grid point
        rotor, compliance = np.asarray(self.rotor_inertia_kg_m2), np.asarray(self.compliance_rad_nm)
        worst = 0.0
        for i in np.argsort(-np.abs(jumps))[:STEPS_CHECKED].tolist():
            q, d1 = np.asarray(path(float(x_grid[i]))), np.asarray(path(float(x_grid[i]), 1))
            zero, step = np.zeros_like(q), d1 * jumps[i]
            link_nm = np.asarray(inverse_dynamics(q, zero, step)) - np.asarray(inverse_dynamics(q, zero, zero)) - rotor * step
            worst = max(worst, float(np.max(np.abs(link_nm) * compliance)))
        return worst

    def windows(self, windows_s: tuple[float, ...], twist_rad: float) -> tuple[float, ...]:
        """The windows for a trajectory whose largest step twists a gear by `twist_rad`."""
        share = min(1.0, twist_rad / self.full_step_rad)
        return tuple(max(self.least_s, share * window_s) for window_s in windows_s)
