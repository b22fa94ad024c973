"""The motion room's compiled IK tracking: Newton steps along a Cartesian path's samples for a six-axis chain (numba).

`Kinematics.ik_along` with `Kinematics._track` is the reference (Pinocchio's kinematics, LAPACK's solve, in
Python): the same iteration, tolerance and checks, on the chain's rows (`ArmModel.rigid_body_rows`: each joint's
placement in its parent and its axis) with the flange's (and tool's) placement in the last joint. The kinematics
differ from Pinocchio's in the last bits only (the order of the sums); every sample is converged to the same
1e-10 pose error, so the joint samples agree to about 1e-12 rad (tests/motion/test_ik_kernels.py bounds them).
"""

from __future__ import annotations


import numpy as np

from orc_rpl.plant.compiled import inlined_kernel, kernel
from orc_rpl.plant.rotation_kernel import axis_rotation

#: Newton steps a sample may take before the full IK is asked (as `Kinematics._track`).
TRACK_STEPS = 8
#: pose error (m and rad, largest component) at which a sample counts as converged (as `Kinematics._track`).
TRACK_TOLERANCE = 1e-10


@inlined_kernel
def pose_and_jacobian(rows: np.ndarray, tip: np.ndarray, q: np.ndarray, pose: np.ndarray, jac: np.ndarray,
                      origins: np.ndarray, axes: np.ndarray) -> None:  # pragma: no cover - compiled
    """The TCP pose (4x4) and its world-aligned geometric Jacobian (6, n) at q of a revolute chain: `rows` the
    joints' placements (rotation row-major 0:9, translation 9:12) and axes (12:15), `tip` the TCP in the last joint's
    frame; origins, axes: (n, 3) scratch for each joint's origin and world axis."""
    n = q.shape[0]
    r = np.eye(3)
    p = np.zeros(3)
    pr = np.empty((3, 3))
    for i in range(n):
        # the joint's frame: the parent's, then its placement, then the rotation about its axis (Rodrigues)
        for a in range(3):
            for b in range(3):
                pr[a, b] = r[a, 0] * rows[i, 3 * 0 + b] + r[a, 1] * rows[i, 3 * 1 + b] + r[a, 2] * rows[i, 3 * 2 + b]
        for a in range(3):
            p[a] = p[a] + r[a, 0] * rows[i, 9] + r[a, 1] * rows[i, 10] + r[a, 2] * rows[i, 11]
        x, y, z = rows[i, 12], rows[i, 13], rows[i, 14]
        j00, j01, j02, j10, j11, j12, j20, j21, j22 = axis_rotation(x, y, z, q[i])
        for a in range(3):
            r0, r1, r2 = pr[a, 0], pr[a, 1], pr[a, 2]
            r[a, 0] = r0 * j00 + r1 * j10 + r2 * j20
            r[a, 1] = r0 * j01 + r1 * j11 + r2 * j21
            r[a, 2] = r0 * j02 + r1 * j12 + r2 * j22
            origins[i, a] = p[a]
            axes[i, a] = pr[a, 0] * x + pr[a, 1] * y + pr[a, 2] * z  # the axis is fixed by its own rotation
    for a in range(3):
        for b in range(3):
            pose[a, b] = r[a, 0] * tip[0, b] + r[a, 1] * tip[1, b] + r[a, 2] * tip[2, b]
        pose[a, 3] = p[a] + r[a, 0] * tip[0, 3] + r[a, 1] * tip[1, 3] + r[a, 2] * tip[2, 3]
        pose[3, a] = 0.0
    pose[3, 3] = 1.0
    for i in range(n):
        # a revolute joint moves the TCP by w x (p_tcp - p_joint) and turns it by w
        wx, wy, wz = axes[i, 0], axes[i, 1], axes[i, 2]
        dx, dy, dz = pose[0, 3] - origins[i, 0], pose[1, 3] - origins[i, 1], pose[2, 3] - origins[i, 2]
        jac[0, i], jac[1, i], jac[2, i] = wy * dz - wz * dy, wz * dx - wx * dz, wx * dy - wy * dx
        jac[3, i], jac[4, i], jac[5, i] = wx, wy, wz


@inlined_kernel
def solve6(a: np.ndarray, b: np.ndarray, x: np.ndarray) -> bool:  # pragma: no cover - compiled
    """x = a^-1 b by Gaussian elimination with partial pivoting (LAPACK dgesv's method; a and b are overwritten);
    False when a is singular (an exactly zero pivot, where dgesv reports info > 0)."""
    n = b.shape[0]
    for k in range(n):
        piv = k
        for i in range(k + 1, n):
            if abs(a[i, k]) > abs(a[piv, k]):
                piv = i
        if a[piv, k] == 0.0:
            return False
        if piv != k:
            for j in range(n):
                a[k, j], a[piv, j] = a[piv, j], a[k, j]
            b[k], b[piv] = b[piv], b[k]
        for i in range(k + 1, n):
            f = a[i, k] / a[k, k]
            for j in range(k + 1, n):
                a[i, j] -= f * a[k, j]
            b[i] -= f * b[k]
    for k in range(n - 1, -1, -1):
        acc = b[k]
        for j in range(k + 1, n):
            acc -= a[k, j] * x[j]
        x[k] = acc / a[k, k]
    return True


@kernel
def track_along(rows: np.ndarray, tip: np.ndarray, poses: np.ndarray, qs: np.ndarray, start: int, q_min: np.ndarray,
                q_max: np.ndarray, limit_rad: float) -> int:  # pragma: no cover - compiled
    """Samples start, start + 1, ... of qs (N, 6) by Newton steps from the previous sample to poses (N, 4, 4), as
    `Kinematics._track` does; stops at the first sample the steps do not settle (not converged, singular, a jump of a
    joint over `limit_rad`, or outside the joint ranges) and returns its index (that sample is the full IK's), or N."""
    n = qs.shape[1]
    pose, jac = np.empty((4, 4)), np.empty((6, n))
    origins, axes = np.empty((n, 3)), np.empty((n, 3))
    err, step = np.empty(6), np.empty(6)
    q = np.empty(n)
    e = np.empty((3, 3))
    for i in range(start, poses.shape[0]):
        for j in range(n):
            q[j] = qs[i - 1, j]
        target = poses[i]
        converged = False
        for _ in range(TRACK_STEPS):
            pose_and_jacobian(rows, tip, q, pose, jac, origins, axes)
            # the rotation still to go, target_R @ R^T: its vee part is the angle error for small angles
            for a in range(3):
                for b in range(3):
                    e[a, b] = target[a, 0] * pose[b, 0] + target[a, 1] * pose[b, 1] + target[a, 2] * pose[b, 2]
            err[0], err[1], err[2] = target[0, 3] - pose[0, 3], target[1, 3] - pose[1, 3], target[2, 3] - pose[2, 3]
            err[3], err[4], err[5] = 0.5 * (e[2, 1] - e[1, 2]), 0.5 * (e[0, 2] - e[2, 0]), 0.5 * (e[1, 0] - e[0, 1])
            worst = 0.0
            for a in range(6):
                worst = max(worst, abs(err[a]))
            if worst < TRACK_TOLERANCE:
                converged = True
                break
            if not solve6(jac, err, step):
                break
            for j in range(n):
                q[j] += step[j]
        if not converged:
            return i
        for j in range(n):
            # (a NaN fails both tests: it is out of range, as in the reference)
            if not (abs(q[j] - qs[i - 1, j]) <= limit_rad and q_min[j] <= q[j] <= q_max[j]):
                return i
        for j in range(n):
            qs[i, j] = q[j]
    return poses.shape[0]
