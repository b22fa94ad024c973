"""The servo room's tuning for elastic gears: per-joint loop bandwidths below each joint's anti-resonance."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import Any

import numpy as np

from orc_rpl.robot.model import ArmModel
from orc_rpl.servo.control import ServoGains
from orc_rpl.servo.gear_observer import EXCESS_TIME_S

#: Poses of j2 and j3 (share of each joint's range) over which the links' largest inertia is sought.
GRID_POINTS = 7

#: The position loop's bandwidth at most this share of the velocity loop's (the cascade stays a cascade).
POSITION_OVER_VELOCITY = 0.25
#: The share with the gears' twist fed forward (GearTwist): the feedback has less to do, and measured on
#: bench_arm_control's moves 0.25, 0.4, 0.6, 0.8 gave 4.70, 3.15, 2.24, 2.07 mm, the last saturating 1.9 %;
#: with the friction estimate and the averaged integral (motion/virtual.py) 0.6, 0.8, 1.0 gave 1.90, 1.77,
#: 1.67 mm at the links and 1.19, 1.06, 1.25 mm at the encoders, each saturating in about 0.4 %.
TWIST_POSITION_OVER_VELOCITY = 0.8

#: Time constant (s) over which the servo's integral torque is averaged into the gears' twist (GearTwist.integral_of):
#: on bench_arm_control's moves 0.05, 0.2, 1.0 s gave 2.19, 1.93, 1.90 mm at the links (with the friction estimate).
TWIST_INTEGRAL_TIME_S = 1.0

#: A joint's averaged integral follows only while its reference moves faster than this (rad/s), and is held
#: otherwise: at rest the integral also holds what the rotor's static friction leaves over (rotor side, not
#: through the gear). On bench_arm_control's moves 0 (always), 0.05, 0.2, 0.4, 0.8 gave 1.766, 1.680, 1.602,
#: 1.602, 1.658 mm at the links.
TWIST_INTEGRAL_MIN_SPEED_RAD_S = 0.2

#: Anti-resonance periods over which a trajectory's time scaling is averaged (the lowest modes: j1, j2).
SMOOTHING_WINDOWS = 2


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
                   gains: ServoGains = ServoGains(),
                   position_over_velocity: float = POSITION_OVER_VELOCITY) -> ServoGains:
    """Gains for joints whose gear is a spring between the rotor (what the encoder sees) and the link.

    The velocity loop of joint j runs at most at its anti-resonance sqrt(k_j / J_link,j) (the
    link's largest inertia, rotor excluded): above it the loop would see the rotor alone and its gain
    M_ii * bandwidth, over the 1 ms step, would make the rotor ring against the gear (j1 and j2 of
    the IRB 2400 at 160 rad/s: kv * h / J_rotor of 4.5 and 3.6, unstable). The position loop is
    capped at `position_over_velocity` of the velocity loop. Joints whose anti-resonance lies above
    the default bandwidth keep the default gains.
    """
    link = link_inertia_max(arm, motor_inertia_kg_m2)
    anti_resonance = np.sqrt(np.asarray(gear_stiffness_nm_rad, dtype=float) / link)
    velocity_bw = np.minimum(anti_resonance, gains.velocity_bw_rad_s)
    position = np.minimum(position_over_velocity * velocity_bw, gains.position_gain_1_s)
    position[velocity_bw >= gains.velocity_bw_rad_s] = gains.position_gain_1_s
    return dataclasses.replace(gains, joint_velocity_bw_rad_s=tuple(float(v) for v in velocity_bw),
                               joint_position_gain_1_s=tuple(float(v) for v in position),
                               gear_stiffness_nm_rad=tuple(float(v) for v in gear_stiffness_nm_rad),
                               rotor_inertia_kg_m2=tuple(float(v) for v in motor_inertia_kg_m2))


class GearTwist:
    """The motor-side references of joints with elastic gears: the link's reference plus the gear's twist.

    A gear of stiffness k carrying the link torque tau_link twists by tau_link / k, so the rotor (what
    the encoder and the servo see) must lead the link by that much for the link to be on its
    reference: q_motor = q_link + tau_link / k and qd_motor = qd_link + d/dt (tau_link / k). tau_link is
    the model's torque of the link reference (the feed-forward the servo computes anyway) without
    the rotor's own inertia, which is on the motor side of the gear. The twist's rate is its
    difference from one servo step to the next (the previous call's last row carried over).

    The rotor's torque for the twist's acceleration (J_rotor d2/dt2 (tau_link / k)) is left out: as a
    second difference over 1 ms steps it turns every kink of the references (a path acceleration
    that changes from one motion cycle to the next) into torque spikes (hand runs of
    `bench_arm_control.py`'s moves on elastic gears: 2.6 % of the cycles saturated with it, 0.8 % without).
    """

    def __init__(self, stiffness_nm_rad: Any, rotor_inertia_kg_m2: Any, period_s: float,
                 integral_time_s: float = TWIST_INTEGRAL_TIME_S) -> None:
        self.compliance_rad_nm = 1.0 / np.asarray(stiffness_nm_rad, dtype=float)
        self.rotor_inertia_kg_m2 = np.asarray(rotor_inertia_kg_m2, dtype=float)
        self.period_s = period_s
        self.twist_rad = np.zeros(len(self.compliance_rad_nm))   #: the twist of the last row commanded (rad)
        self._fresh = True
        #: The servo's integral torque (a callable returning it), None: the model's torque alone. What the
        #: integral holds beyond the friction the feed-forward knows is torque the links need and the model
        #: lacks (an undeclared payload, masses a few percent off): it passes through the gears and twists
        #: them as the model's torque does. Averaged over `integral_time_s` (a first-order filter, one
        #: step per call), so the references move smoothly and the twist does not follow the loop's ripple.
        self.integral_of: Callable[[], np.ndarray] | None = None
        self.integral_time_s = float(integral_time_s)
        self.integral_min_speed_rad_s = TWIST_INTEGRAL_MIN_SPEED_RAD_S
        self.extra_torque_nm = np.zeros(len(self.compliance_rad_nm))   #: the averaged integral in the twist (N m)
        #: Where set, the torque the model lacks as a gear-torque observer sees it (servo/gear_observer.py,
        #: `excess_nm`), low-passed over `excess_time_s`, instead of the servo's integral (same hold at rest).
        self.excess_of: Callable[[], np.ndarray] | None = None
        self.excess_time_s = EXCESS_TIME_S

    def reset(self) -> None:
        """Forget the last row: the next call starts at rest (no rate from a stale row)."""
        self._fresh = True

    def forget(self) -> None:
        """A new start (a reset of the plant): no averaged integral, no last row."""
        self.extra_torque_nm[:] = 0.0
        self.reset()

    def _moving(self, qd_ref: np.ndarray) -> np.ndarray | float:
        """1 for joints whose reference moves faster than `integral_min_speed_rad_s`, 0 for the others."""
        if self.integral_min_speed_rad_s <= 0.0:
            return 1.0
        return (np.abs(qd_ref) > self.integral_min_speed_rad_s).astype(float)

    def motor_references(self, q_ref: np.ndarray, qd_ref: np.ndarray, qdd_ref: np.ndarray,
                         tau_ff: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Motor-side (q_ref, qd_ref) rows for link-side rows; tau_ff: the model's torque rows of the link
        references (armature included, as the model's)."""
        link_torque = tau_ff - self.rotor_inertia_kg_m2 * qdd_ref
        source, time_s = ((self.excess_of, self.excess_time_s) if self.excess_of is not None
                          else (self.integral_of, self.integral_time_s))
        if source is not None:
            share = (1.0 - np.exp(-len(q_ref) * self.period_s / time_s)) * self._moving(qd_ref[-1])
            self.extra_torque_nm += share * (source() - self.extra_torque_nm)
            link_torque += self.extra_torque_nm
        twist = link_torque * self.compliance_rad_nm
        before = twist[:1] if self._fresh else self.twist_rad[None, :]
        rate = np.diff(twist, axis=0, prepend=before) * (1.0 / self.period_s)
        self.twist_rad, self._fresh = twist[-1].copy(), False
        return q_ref + twist, qd_ref + rate

    def hold(self, q: np.ndarray, tau_nm: np.ndarray) -> None:
        """At rest at q with the model's torques tau_nm (a reset): the twist the gears have, no rate."""
        self.forget()
        self.twist_rad = tau_nm * self.compliance_rad_nm   # at rest the link torque is the model's, all of it


def anti_resonance_periods_s(arm: ArmModel, motor_inertia_kg_m2: Any, gear_stiffness_nm_rad: Any,
                             count: int = SMOOTHING_WINDOWS) -> tuple[float, ...]:
    """The periods (s) of the `count` lowest anti-resonances (at the links' largest inertia), longest first."""
    link = link_inertia_max(arm, motor_inertia_kg_m2)
    anti_resonance = np.sort(np.sqrt(np.asarray(gear_stiffness_nm_rad, dtype=float) / link))
    return tuple(float(2.0 * np.pi / w) for w in anti_resonance[:count])


def smoothing_windows_s(arm: ArmModel, motor_inertia_kg_m2: Any, gear_stiffness_nm_rad: Any,
                        share: float = 1.0) -> tuple[float, ...]:
    """The windows (s) a trajectory's time scaling is averaged over, each in turn (motion/trajectory.py `smoothed`),
    longest first: the lowest anti-resonance periods (an average over a mode's period does not excite it, and keeps
    the torques free of steps), or `share` of them (benchmarks: bench_arm_control --smoothing-share). Under the
    state feedback a trajectory is averaged over as much of them as its steps' twist of the gears calls for
    (motion/gear_steps.py)."""
    return tuple(share * period for period in anti_resonance_periods_s(arm, motor_inertia_kg_m2, gear_stiffness_nm_rad))
