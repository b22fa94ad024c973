"""The servo room's adaptive feed-forward: friction and payload the model lacks, learnt from the servo's integral."""

from __future__ import annotations

from typing import Any

import numpy as np

from orc_rpl.servo.control import FRICTION_SMOOTH_RAD_S, JointServo

#: Forgetting factor of the recursive least squares, per motion cycle (memory about 1 / (1 - f) cycles: 4 s).
FORGETTING = 0.999
#: The estimate's prior spread: Coulomb (N m), viscous (N m s/rad) and payload (kg) a cycle may move it by.
PRIOR = (50.0, 50.0, 5.0)
#: Below this reference speed of every joint (rad/s) the arm is at rest: the estimate does not forget
#: (nothing to learn friction from; forgetting would only grow its covariance without bound: wind-up).
MOVING_RAD_S = 0.01
#: The friction estimate stays within [-1, EXCESS_MAX] times the nominal (a cold start: about 1.2 above it).
EXCESS_MAX = 2.0
#: Standard gravity (m/s^2).
GRAVITY_M_S2 = 9.81


class FeedForwardAdaptation:
    """Estimates what the model's feed-forward lacks, and adds it, so the feedback need not carry it.

    The servo's integral torque I (per joint) is what the feedback has found the model lacking: the
    friction above the nominal (a cold start doubles it) and the weight of a payload nobody declared.
    Each motion cycle a recursive least squares (forgetting FORGETTING) fits
    I + (what is already added) = dFc_j tanh(qd_j / 0.05) + dFv_j qd_j + dm * g_j(q), with g_j the joint torque
    1 kg at the flange weighs; the new estimate goes into the servo's friction (`set_friction`) and its
    model's payload, and the integral gives up what was added (bumpless: the total torque does not jump).
    While a motor saturates or an integral is at its limit the estimate is held: the integral then
    says nothing about the model (measured: learning through saturation diverged within 30 fast moves).
    With gears that bound the loops' gains (elastic gears: servo/two_mass.py) the integral alone
    takes seconds to learn a cold start; the estimate carries it from move to move.
    """

    def __init__(self, servo: JointServo, coulomb_nm: Any, viscous_nm_s: Any, jacobian: Any) -> None:
        self.servo = servo
        n = servo.arm.n_joints
        self._n = n
        self._coulomb0 = np.array(coulomb_nm, dtype=float)
        self._viscous0 = np.array(viscous_nm_s, dtype=float)
        self._jacobian = jacobian   #: q -> (3, n) linear Jacobian of the flange
        self.theta = np.zeros(2 * n + 1)   #: dFc (n), dFv (n), dm (kg)
        self._p = np.diag(np.concatenate([np.full(n, PRIOR[0] ** 2), np.full(n, PRIOR[1] ** 2), [PRIOR[2] ** 2]]))
        self._added = np.zeros(n)          #: the torque the estimate adds now (N m)
        self._payload_applied: float | None = None
        self._declared_kg = 0.0

    def regressor(self, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """(n, 2n + 1): each joint's torque per unit of dFc, dFv and dm at the reference (q, qd)."""
        n = self._n
        phi = np.zeros((n, 2 * n + 1))
        idx = np.arange(n)
        phi[idx, idx] = np.tanh(qd / FRICTION_SMOOTH_RAD_S)
        phi[idx, n + idx] = qd
        phi[:, 2 * n] = self._jacobian(q)[2] * GRAVITY_M_S2
        return phi

    def update(self, q_ref: np.ndarray, qd_ref: np.ndarray) -> None:
        """One motion cycle: fit the integral at the last reference, then move the estimate into the feed-forward."""
        servo, n = self.servo, self._n
        payload = float(servo.arm.payload[0])
        if self._payload_applied is None or payload != self._payload_applied:
            self._declared_kg = payload   # a move declared its load: the estimate is on top of it
        phi = self.regressor(q_ref, qd_ref)
        integral = servo.integral
        if True in servo.saturated.tolist() or np.any(np.abs(integral) >= 0.99 * servo._integral_max):
            self._apply(phi)   # a saturated motor or a full integral says nothing about the model: hold
            return
        forgetting = FORGETTING if float(np.max(np.abs(qd_ref))) >= MOVING_RAD_S else 1.0
        y = servo.integral + self._added
        p, theta = self._p, self.theta
        for j in range(n):   # one joint at a time: scalar updates, no matrix inverse
            h = phi[j]
            ph = p @ h
            gain = ph / (forgetting + h @ ph)
            theta += gain * (y[j] - h @ theta)
            p -= np.outer(gain, ph)
        p /= forgetting
        # a physical estimate: friction not below zero nor beyond EXCESS_MAX, payload not below nothing
        np.clip(theta[:n], -self._coulomb0, EXCESS_MAX * self._coulomb0, out=theta[:n])
        np.clip(theta[n:2 * n], -self._viscous0, EXCESS_MAX * self._viscous0, out=theta[n:2 * n])
        theta[2 * n] = max(theta[2 * n], -self._declared_kg)
        self._apply(phi)

    def _apply(self, phi: np.ndarray) -> None:
        """The estimate into the servo's friction and payload; the integral gives up what it adds anew."""
        servo, n, theta = self.servo, self._n, self.theta
        added = phi @ theta
        servo.integral = np.clip(servo.integral - (added - self._added), servo._integral_min, servo._integral_max)
        self._added = added
        servo.set_friction(self._coulomb0 + theta[:n], self._viscous0 + theta[n:2 * n])
        self._payload_applied = self._declared_kg + float(theta[2 * n])
        servo.arm.set_payload(self._payload_applied)
