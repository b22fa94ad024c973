"""The servo room's tuning for elastic gears: per-joint loop bandwidths below each joint's anti-resonance."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from orc_rpl.robot.model import ArmModel
from orc_rpl.servo.control import ServoGains

#: Poses of j2 and j3 (share of each joint's range) over which the links' largest inertia is sought.
GRID_POINTS = 7

#: The position loop's bandwidth at most this share of the velocity loop's (the cascade stays a cascade).
POSITION_OVER_VELOCITY = 0.25


def link_inertia_max(arm: ArmModel, motor_inertia_kg_m2: Any) -> np.ndarray:
    """Each joint's largest link-side inertia (kg m^2): the model's M_ii without the rotor, over j2 and j3's ranges."""
    n = arm.n_joints
    base = np.array(arm.home_q, dtype=float)
    worst = np.zeros(n)
    for a in np.linspace(arm.q_min[1], arm.q_max[1], GRID_POINTS):
        for b in np.linspace(arm.q_min[2], arm.q_max[2], GRID_POINTS):
            q = base.copy()
            q[1], q[2] = a, b
            np.maximum(worst, arm.mass_matrix_diagonal_unchecked(q), out=worst)
    return np.maximum(worst - np.asarray(motor_inertia_kg_m2, dtype=float), 1e-9)


def two_mass_gains(arm: ArmModel, motor_inertia_kg_m2: Any, gear_stiffness_nm_rad: Any,
                   gains: ServoGains = ServoGains()) -> ServoGains:
    """Gains for joints whose gear is a spring between the rotor (what the encoder sees) and the link.

    The velocity loop of joint j runs at most at its anti-resonance sqrt(k_j / J_link,j) (the
    link's largest inertia, rotor excluded): above it the loop would see the rotor alone and its gain
    M_ii * bandwidth, over the 1 ms step, would make the rotor ring against the gear (j1 and j2 of
    the IRB 2400 at 160 rad/s: kv * h / J_rotor of 4.5 and 3.6, unstable). The position loop is
    capped at POSITION_OVER_VELOCITY of the velocity loop. Joints whose anti-resonance lies above
    the default bandwidth keep the default gains.
    """
    link = link_inertia_max(arm, motor_inertia_kg_m2)
    anti_resonance = np.sqrt(np.asarray(gear_stiffness_nm_rad, dtype=float) / link)
    velocity_bw = np.minimum(anti_resonance, gains.velocity_bw_rad_s)
    position = np.minimum(POSITION_OVER_VELOCITY * velocity_bw, gains.position_gain_1_s)
    position[velocity_bw >= gains.velocity_bw_rad_s] = gains.position_gain_1_s
    return dataclasses.replace(gains, joint_velocity_bw_rad_s=tuple(float(v) for v in velocity_bw),
                               joint_position_gain_1_s=tuple(float(v) for v in position),
                               gear_stiffness_nm_rad=tuple(float(v) for v in gear_stiffness_nm_rad),
                               rotor_inertia_kg_m2=tuple(float(v) for v in motor_inertia_kg_m2))
