"""The servo room's inverse dynamics compiled: the recursive Newton-Euler algorithm of a revolute chain, in numba.

Pinocchio's RNEA (robot/model.py) is the reference; this one works on the rows of
`ArmModel.rigid_body_rows` (made again when the payload changes) so that the drives' motion cycle
(servo/drive_kernels.py) gets its feed-forward without leaving compiled code. Spatial vectors as
Pinocchio writes them: motion (linear, angular) and force (linear, angular), in each body's frame;
the base accelerates against gravity. Its torques differ from Pinocchio's in the last bits only
(the order of the sums; tests/servo/test_drive_kernels.py bounds it at 1e-12 relative).
"""

from __future__ import annotations


import numpy as np

from orc_rpl.plant.compiled import inlined_kernel, kernel
from orc_rpl.plant.rotation_kernel import axis_rotation

#: Columns of a row of `ArmModel.rigid_body_rows`.
ROTATION, TRANSLATION, AXIS, MASS, LEVER, INERTIA, ARMATURE = 0, 9, 12, 15, 16, 19, 28


@inlined_kernel
def _in_child(work: np.ndarray, i: int, px: float, py: float, pz: float, l0: float, l1: float, l2: float, w0: float,
              w1: float, w2: float) -> tuple[float, float, float, float, float, float]:  # pragma: no cover - compiled
    """A motion (linear l, angular w) of body i's parent in body i's frame (Pinocchio's actInv): R^T (l - p x w),
    R^T w, with R (row-major in work[i, 0:9]) and p body i's placement in its parent at the joint's angle."""
    ux, uy, uz = l0 - (py * w2 - pz * w1), l1 - (pz * w0 - px * w2), l2 - (px * w1 - py * w0)
    return (work[i, 0] * ux + work[i, 3] * uy + work[i, 6] * uz, work[i, 1] * ux + work[i, 4] * uy + work[i, 7] * uz,
            work[i, 2] * ux + work[i, 5] * uy + work[i, 8] * uz, work[i, 0] * w0 + work[i, 3] * w1 + work[i, 6] * w2,
            work[i, 1] * w0 + work[i, 4] * w1 + work[i, 7] * w2, work[i, 2] * w0 + work[i, 5] * w1 + work[i, 8] * w2)


@inlined_kernel
def _inertia_times(body: np.ndarray, i: int, l0: float, l1: float, l2: float, w0: float, w1: float,
                   w2: float) -> tuple[float, float, float, float, float, float]:  # pragma: no cover - compiled
    """Body i's spatial inertia times a motion (linear l, angular w) in its frame: (mass (l - c x w), Ic w + c x f)."""
    m, cx, cy, cz = body[i, MASS], body[i, LEVER], body[i, LEVER + 1], body[i, LEVER + 2]
    f0, f1, f2 = m * (l0 - (cy * w2 - cz * w1)), m * (l1 - (cz * w0 - cx * w2)), m * (l2 - (cx * w1 - cy * w0))
    return (f0, f1, f2,
            body[i, INERTIA] * w0 + body[i, INERTIA + 1] * w1 + body[i, INERTIA + 2] * w2 + (cy * f2 - cz * f1),
            body[i, INERTIA + 3] * w0 + body[i, INERTIA + 4] * w1 + body[i, INERTIA + 5] * w2 + (cz * f0 - cx * f2),
            body[i, INERTIA + 6] * w0 + body[i, INERTIA + 7] * w1 + body[i, INERTIA + 8] * w2 + (cx * f1 - cy * f0))


@inlined_kernel
def rnea_row(body: np.ndarray, gravity: np.ndarray, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
             tau: np.ndarray, work: np.ndarray) -> None:  # pragma: no cover - compiled
    """tau = RNEA(q, qd, qdd) for one state; work: a (n, 15) scratch array (a body's rotation 0:9, its force 9:15)."""
    rotations(body, q, work)
    rnea_rotated(body, gravity, qd, qdd, tau, work)


@inlined_kernel
def rotations(body: np.ndarray, q: np.ndarray, work: np.ndarray) -> None:  # pragma: no cover - compiled
    """Each body's rotation from its parent at the angles q into work[:, 0:9] (`rnea_row`'s first part)."""
    for i in range(q.shape[0]):
        x, y, z = body[i, AXIS], body[i, AXIS + 1], body[i, AXIS + 2]
        # joint rotation (Rodrigues) and the placement's before it: R = P Rj, rows of R map child to parent
        j00, j01, j02, j10, j11, j12, j20, j21, j22 = axis_rotation(x, y, z, q[i])
        for r in range(3):
            p0, p1, p2 = body[i, ROTATION + 3 * r], body[i, ROTATION + 3 * r + 1], body[i, ROTATION + 3 * r + 2]
            work[i, 3 * r] = p0 * j00 + p1 * j10 + p2 * j20
            work[i, 3 * r + 1] = p0 * j01 + p1 * j11 + p2 * j21
            work[i, 3 * r + 2] = p0 * j02 + p1 * j12 + p2 * j22


@inlined_kernel
def rnea_rotated(body: np.ndarray, gravity: np.ndarray, qd: np.ndarray, qdd: np.ndarray, tau: np.ndarray,
                 work: np.ndarray) -> None:  # pragma: no cover - compiled
    """`rnea_row` after `rotations`: work[:, 0:9] holds the bodies' rotations at the state's angles (several
    RNEAs at the same angles, as the mass matrix's columns, make them once)."""
    n = qd.shape[0]
    # forward: each body's velocity and acceleration in its own frame
    vl0 = vl1 = vl2 = vw0 = vw1 = vw2 = 0.0
    al0, al1, al2 = -gravity[0], -gravity[1], -gravity[2]
    aw0 = aw1 = aw2 = 0.0
    for i in range(n):
        x, y, z = body[i, AXIS], body[i, AXIS + 1], body[i, AXIS + 2]
        px, py, pz = body[i, TRANSLATION], body[i, TRANSLATION + 1], body[i, TRANSLATION + 2]
        # actInv: w' = R^T w, v' = R^T (v - p x w); plus the joint's S qd (velocity) and S qdd (acceleration)
        nvl0, nvl1, nvl2, nvw0, nvw1, nvw2 = _in_child(work, i, px, py, pz, vl0, vl1, vl2, vw0, vw1, vw2)
        nvw0, nvw1, nvw2 = nvw0 + x * qd[i], nvw1 + y * qd[i], nvw2 + z * qd[i]
        nal0, nal1, nal2, naw0, naw1, naw2 = _in_child(work, i, px, py, pz, al0, al1, al2, aw0, aw1, aw2)
        naw0, naw1, naw2 = naw0 + x * qdd[i], naw1 + y * qdd[i], naw2 + z * qdd[i]
        # + v x (S qd): linear v_lin x w_j, angular v_ang x w_j
        wx, wy, wz = x * qd[i], y * qd[i], z * qd[i]
        nal0 += nvl1 * wz - nvl2 * wy
        nal1 += nvl2 * wx - nvl0 * wz
        nal2 += nvl0 * wy - nvl1 * wx
        naw0 += nvw1 * wz - nvw2 * wy
        naw1 += nvw2 * wx - nvw0 * wz
        naw2 += nvw0 * wy - nvw1 * wx
        vl0, vl1, vl2, vw0, vw1, vw2 = nvl0, nvl1, nvl2, nvw0, nvw1, nvw2
        al0, al1, al2, aw0, aw1, aw2 = nal0, nal1, nal2, naw0, naw1, naw2
        # f = I a + v x* (I v); I m = (mass (v - c x w), Ic w + c x f)
        fl0, fl1, fl2, fa0, fa1, fa2 = _inertia_times(body, i, al0, al1, al2, aw0, aw1, aw2)
        hl0, hl1, hl2, ha0, ha1, ha2 = _inertia_times(body, i, vl0, vl1, vl2, vw0, vw1, vw2)
        # v x* h = (w x h_lin, w x h_ang + v x h_lin)
        work[i, 9] = fl0 + (vw1 * hl2 - vw2 * hl1)
        work[i, 10] = fl1 + (vw2 * hl0 - vw0 * hl2)
        work[i, 11] = fl2 + (vw0 * hl1 - vw1 * hl0)
        work[i, 12] = fa0 + (vw1 * ha2 - vw2 * ha1) + (vl1 * hl2 - vl2 * hl1)
        work[i, 13] = fa1 + (vw2 * ha0 - vw0 * ha2) + (vl2 * hl0 - vl0 * hl2)
        work[i, 14] = fa2 + (vw0 * ha1 - vw1 * ha0) + (vl0 * hl1 - vl1 * hl0)
    # backward: the joint's torque from its body's force, the force handed to the parent (act: R f, R n + p x R f)
    for i in range(n - 1, -1, -1):
        tau[i] = (body[i, AXIS] * work[i, 12] + body[i, AXIS + 1] * work[i, 13] + body[i, AXIS + 2] * work[i, 14]
                  + body[i, ARMATURE] * qdd[i])
        if i > 0:
            f0 = work[i, 0] * work[i, 9] + work[i, 1] * work[i, 10] + work[i, 2] * work[i, 11]
            f1 = work[i, 3] * work[i, 9] + work[i, 4] * work[i, 10] + work[i, 5] * work[i, 11]
            f2 = work[i, 6] * work[i, 9] + work[i, 7] * work[i, 10] + work[i, 8] * work[i, 11]
            px, py, pz = body[i, TRANSLATION], body[i, TRANSLATION + 1], body[i, TRANSLATION + 2]
            work[i - 1, 9] += f0
            work[i - 1, 10] += f1
            work[i - 1, 11] += f2
            work[i - 1, 12] += work[i, 0] * work[i, 12] + work[i, 1] * work[i, 13] + work[i, 2] * work[i, 14] + (py * f2 - pz * f1)
            work[i - 1, 13] += work[i, 3] * work[i, 12] + work[i, 4] * work[i, 13] + work[i, 5] * work[i, 14] + (pz * f0 - px * f2)
            work[i - 1, 14] += work[i, 6] * work[i, 12] + work[i, 7] * work[i, 13] + work[i, 8] * work[i, 14] + (px * f1 - py * f0)


@inlined_kernel
def mass_diagonal(body: np.ndarray, q: np.ndarray, out: np.ndarray) -> None:  # pragma: no cover - compiled
    """The mass matrix's diagonal M_ii(q) (Pinocchio's `crba` diagonal, armature included): each joint's axis
    through the rotational inertia, about the joint, of the bodies it carries (composited from the tip)."""
    n = q.shape[0]
    mass = 0.0
    h0 = h1 = h2 = 0.0                                 # first moment of the carried bodies (kg m), frame i
    j00 = j01 = j02 = j11 = j12 = j22 = 0.0            # their inertia about frame i's origin (symmetric)
    r = np.empty(9)                                    # the child's rotation into frame i
    for i in range(n - 1, -1, -1):
        if i < n - 1:
            # the composite of the child (frame i+1) in this frame: x' = R x + p, R = placement * joint(q)
            x, y, z = body[i + 1, AXIS], body[i + 1, AXIS + 1], body[i + 1, AXIS + 2]
            k00, k01, k02, k10, k11, k12, k20, k21, k22 = axis_rotation(x, y, z, q[i + 1])
            for row in range(3):
                p0 = body[i + 1, ROTATION + 3 * row]
                p1, p2 = body[i + 1, ROTATION + 3 * row + 1], body[i + 1, ROTATION + 3 * row + 2]
                r[3 * row] = p0 * k00 + p1 * k10 + p2 * k20
                r[3 * row + 1] = p0 * k01 + p1 * k11 + p2 * k21
                r[3 * row + 2] = p0 * k02 + p1 * k12 + p2 * k22
            px, py, pz = body[i + 1, TRANSLATION], body[i + 1, TRANSLATION + 1], body[i + 1, TRANSLATION + 2]
            # R J R^T
            a00 = r[0] * j00 + r[1] * j01 + r[2] * j02
            a01 = r[0] * j01 + r[1] * j11 + r[2] * j12
            a02 = r[0] * j02 + r[1] * j12 + r[2] * j22
            a10 = r[3] * j00 + r[4] * j01 + r[5] * j02
            a11 = r[3] * j01 + r[4] * j11 + r[5] * j12
            a12 = r[3] * j02 + r[4] * j12 + r[5] * j22
            a20 = r[6] * j00 + r[7] * j01 + r[8] * j02
            a21 = r[6] * j01 + r[7] * j11 + r[8] * j12
            a22 = r[6] * j02 + r[7] * j12 + r[8] * j22
            n00 = a00 * r[0] + a01 * r[1] + a02 * r[2]
            n01 = a00 * r[3] + a01 * r[4] + a02 * r[5]
            n02 = a00 * r[6] + a01 * r[7] + a02 * r[8]
            n11 = a10 * r[3] + a11 * r[4] + a12 * r[5]
            n12 = a10 * r[6] + a11 * r[7] + a12 * r[8]
            n22 = a20 * r[6] + a21 * r[7] + a22 * r[8]
            g0 = r[0] * h0 + r[1] * h1 + r[2] * h2
            g1 = r[3] * h0 + r[4] * h1 + r[5] * h2
            g2 = r[6] * h0 + r[7] * h1 + r[8] * h2
            # shifted by p: + 2 (g.p) I - g p^T - p g^T + mass (|p|^2 I - p p^T)
            gp, pp = g0 * px + g1 * py + g2 * pz, px * px + py * py + pz * pz
            j00 = n00 + 2.0 * gp - 2.0 * g0 * px + mass * (pp - px * px)
            j11 = n11 + 2.0 * gp - 2.0 * g1 * py + mass * (pp - py * py)
            j22 = n22 + 2.0 * gp - 2.0 * g2 * pz + mass * (pp - pz * pz)
            j01 = n01 - g0 * py - px * g1 - mass * px * py
            j02 = n02 - g0 * pz - px * g2 - mass * px * pz
            j12 = n12 - g1 * pz - py * g2 - mass * py * pz
            h0, h1, h2 = g0 + mass * px, g1 + mass * py, g2 + mass * pz
        else:
            mass = 0.0
        # + this body: Ic + m (|c|^2 I - c c^T) about its frame's origin
        m, cx, cy, cz = body[i, MASS], body[i, LEVER], body[i, LEVER + 1], body[i, LEVER + 2]
        cc = cx * cx + cy * cy + cz * cz
        j00 += body[i, INERTIA] + m * (cc - cx * cx)
        j11 += body[i, INERTIA + 4] + m * (cc - cy * cy)
        j22 += body[i, INERTIA + 8] + m * (cc - cz * cz)
        j01 += body[i, INERTIA + 1] - m * cx * cy
        j02 += body[i, INERTIA + 2] - m * cx * cz
        j12 += body[i, INERTIA + 5] - m * cy * cz
        h0, h1, h2 = h0 + m * cx, h1 + m * cy, h2 + m * cz
        mass += m
        x, y, z = body[i, AXIS], body[i, AXIS + 1], body[i, AXIS + 2]
        out[i] = (x * (j00 * x + j01 * y + j02 * z) + y * (j01 * x + j11 * y + j12 * z)
                  + z * (j02 * x + j12 * y + j22 * z) + body[i, ARMATURE])


@kernel
def mass_matrix_block(body: np.ndarray, q: np.ndarray, joints: np.ndarray, out: np.ndarray) -> None:  # pragma: no cover
    """The block of the mass matrix M(q) (armature included) of the rows and columns `joints`, into out: a column
    is the RNEA of a unit acceleration of its joint, at rest, without gravity (`rnea_rotated` a column, on the
    rotations made once)."""
    n, m = q.shape[0], joints.shape[0]
    zero, unit, tau, work = np.zeros(3), np.zeros(n), np.empty(n), np.empty((n, 15))
    speed = np.zeros(n)
    rotations(body, q, work)   # the same angles for every column: the rotations once (the forces overwrite 9:15 only)
    for c in range(m):
        unit[joints[c]] = 1.0
        rnea_rotated(body, zero, speed, unit, tau, work)
        unit[joints[c]] = 0.0
        for r in range(c + 1):   # the upper triangle, mirrored (symmetric to the bit, as Pinocchio's is made)
            out[r, c] = out[c, r] = tau[joints[r]]
