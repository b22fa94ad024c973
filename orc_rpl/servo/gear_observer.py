"""The servo room's gear-torque observer: each elastic gear's torque seen from the motor side, without link sensors."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from orc_rpl.robot.friction import friction_torque_nm
from orc_rpl.servo.control import FRICTION_SMOOTH_RAD_S

#: The observer's bandwidth (rad/s): its gear torque is the true one low-passed at this. Updated once a motion
#: cycle (4 ms): 250 keeps K * dt at 1. On bench_arm_control's moves (excess low-passed over 0.2 s) 150, 250
#: gave 1.467, 1.473 mm at the links; 100 with the excess taken against the reference's model torque 1.652.
OBSERVER_BW_RAD_S = 250.0

#: Time constant (s) over which the observed excess torque is low-passed into the gears' twist (GearTwist):
#: on bench_arm_control's moves 0.05, 0.1, 0.15, 0.2, 0.3 gave 9.16, 8.02, 1.58, 1.47, 1.55 mm at the links
#: (the shorter ones close a loop through the motor's torque that rings).
EXCESS_TIME_S = 0.2


class GearTorqueObserver:
    """Each elastic gear's torque from the rotor's side (a momentum observer, after De Luca et al.), and the
    part of it the controller's model lacks.

    The rotor obeys J_r qdd_m = tau_m - tau_friction - tau_gear: what the motor's torque leaves after
    the rotor's own inertia and friction goes through the gear. Differentiating the encoder twice
    would amplify its noise; the observer r = K (integral(tau_m - tau_friction - r) dt - J_r qd_m) has
    dr/dt = K (tau_gear - r): the gear torque low-passed at K, from the measured speed and the
    drive's mean torque over each servo call. Its error is the friction estimate's (the controller's
    gearbox estimate, about 10 % of the cold friction while the rotor turns fast; near standstill
    the static friction, anything up to the Coulomb friction, is not observable).

    `excess_nm` is the observed torque less the model's link torque at the measured state (the rotor's
    angle less the observed twist, its speed, its acceleration low-passed at K, the same filter as
    the observer's): what the model lacks (an undeclared payload, masses a few percent off), the
    tracking's own torques left out, so feeding it into the twist does not close a loop on them.
    """

    def __init__(self, rotor_inertia_kg_m2: Any, stiffness_nm_rad: Any,
                 inverse_dynamics: Callable[[np.ndarray, np.ndarray, np.ndarray], Any],
                 bandwidth_rad_s: float = OBSERVER_BW_RAD_S) -> None:
        self.rotor_inertia_kg_m2 = np.asarray(rotor_inertia_kg_m2, dtype=float)
        self.compliance_rad_nm = 1.0 / np.asarray(stiffness_nm_rad, dtype=float)
        self.bandwidth_rad_s = float(bandwidth_rad_s)
        self.inverse_dynamics = inverse_dynamics   #: the servo model's rigid-body torques (armature included)
        n = len(self.rotor_inertia_kg_m2)
        self.torque_nm = np.zeros(n)     #: the observed gear torque (N m)
        self.excess_nm = np.zeros(n)     #: the observed torque less the model's at the measured state (N m)
        #: the rotor's friction the controller estimates, (Coulomb N m, viscous N m s/rad) or None, as a callable
        self.friction_of: Callable[[], tuple[np.ndarray, np.ndarray] | None] | None = None
        self._sum, self._model_nm = np.zeros(n), np.zeros(n)
        self._qd_before, self._qdd = np.zeros(n), np.zeros(n)

    def reset(self, torque_nm: Any) -> None:
        """At rest with a known gear torque (a reset: the model's weight torques); no excess."""
        self.torque_nm = np.array(torque_nm, dtype=float)
        self._model_nm = self.torque_nm.copy()
        self.excess_nm = np.zeros(len(self.torque_nm))
        self._sum = self.torque_nm / self.bandwidth_rad_s
        self._qd_before, self._qdd = np.zeros(len(self.torque_nm)), np.zeros(len(self.torque_nm))

    def update(self, q_motor_rad: np.ndarray, qd_motor_rad_s: np.ndarray, tau_motor_nm: np.ndarray, dt_s: float) -> None:
        """After dt_s of the motors' mean torque tau_motor_nm; q_motor_rad, qd_motor_rad_s: the encoders' angles and
        speeds now."""
        drive = tau_motor_nm - self.torque_nm
        friction = self.friction_of() if self.friction_of is not None else None
        if friction is not None:   # smoothed as the servo's feed-forward smooths it (the figures above used that)
            drive -= friction_torque_nm(*friction, qd_motor_rad_s, FRICTION_SMOOTH_RAD_S)
        self._sum += drive * dt_s
        self.torque_nm = self.bandwidth_rad_s * (self._sum - self.rotor_inertia_kg_m2 * qd_motor_rad_s)
        share = min(1.0, self.bandwidth_rad_s * dt_s)   # the same low-pass for the model's side
        self._qdd += share * ((qd_motor_rad_s - self._qd_before) / dt_s - self._qdd)
        self._qd_before = np.array(qd_motor_rad_s, dtype=float)
        # the link torque: the model's rigid-body torque less the rotor's own (the armature's) on its acceleration
        model = (np.array(self.inverse_dynamics(q_motor_rad - self.twist_rad, qd_motor_rad_s, self._qdd))
                 - self.rotor_inertia_kg_m2 * self._qdd)
        self._model_nm += share * (model - self._model_nm)
        self.excess_nm = self.torque_nm - self._model_nm

    @property
    def twist_rad(self) -> np.ndarray:
        """The observed twist of each gear (rad): the rotor ahead of the link by this."""
        return self.torque_nm * self.compliance_rad_nm
