"""Path geometry: joint, straight-line, circular and function paths sampled densely in joint space."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from orc_rpl.errors import JointLimit, PlanningError, Unreachable, UsageError
from orc_rpl.motion.kinematics import Kinematics
from orc_rpl.motion.specs import CartesianMotion, FunctionMotion, JointMotion

#: sampling density of Cartesian paths: the joint spline between samples stays within microns of the line
CART_STEP_M = 0.01
CART_STEP_RAD = math.radians(3.0)
JOINT_STEP_RAD = 0.02
MAX_SAMPLES = 241


@dataclass(slots=True)
class DensePath:
    """Joint samples along a path, with each sample's TCP position, owning motion and path coordinate s."""

    q: np.ndarray       #: (N, n) joint positions, rad
    tcp: np.ndarray     #: (N, 3) TCP positions, m
    owner: np.ndarray   #: (N,) id of the motion each sample belongs to
    s: np.ndarray       #: (N,) that motion's path coordinate in [0, 1]

    def __len__(self) -> int:
        return len(self.q)

    def then(self, other: DensePath) -> DensePath:
        """This path followed by `other` (whose first sample repeats this one's last and is dropped)."""
        return DensePath(
            np.vstack([self.q, other.q[1:]]),
            np.vstack([self.tcp, other.tcp[1:]]),
            np.concatenate([self.owner, other.owner[1:]]),
            np.concatenate([self.s, other.s[1:]]),
        )

    def cut(self, i0: int, i1: int | None = None) -> DensePath:
        """Samples i0..i1 (inclusive of i1; None: to the end)."""
        sl = slice(i0, None if i1 is None else i1 + 1)
        return DensePath(self.q[sl], self.tcp[sl], self.owner[sl], self.s[sl])

    def length_rad(self) -> float:
        """Joint-space chord length."""
        return float(np.sum(np.linalg.norm(np.diff(self.q, axis=0), axis=1)))


def _samples(count_float: float) -> int:
    return int(min(MAX_SAMPLES, max(9, math.ceil(count_float) + 1)))


def _dense(kin: Kinematics, qs: np.ndarray, tool: np.ndarray | None, owner: int, s: np.ndarray) -> DensePath:
    return DensePath(qs, kin.tcp_positions(qs, tool), np.full(len(qs), owner, dtype=int), s)


def joint_segments(kin: Kinematics, q_start: np.ndarray, motion: JointMotion, owner: int) -> list[DensePath]:
    """Straight joint-space segments through the via points to the target; s runs 0..1 over the whole motion."""
    corners = [np.asarray(q_start, dtype=float)] + [np.array(p) for p in motion.via_rad] + [np.array(motion.target_rad)]
    for i, c in enumerate(corners[1:], start=1):
        if len(c) != kin.n:
            raise UsageError(f"joint motion point {i} has {len(c)} values; the robot has {kin.n} joints")
        kin.check_limits(c, "joint target" if i == len(corners) - 1 else f"via point {i}")
    lengths = [float(np.linalg.norm(b - a)) for a, b in zip(corners, corners[1:])]
    total = sum(lengths)
    out: list[DensePath] = []
    done = 0.0
    for a, b, seg_len in zip(corners, corners[1:], lengths):
        if seg_len < 1e-9:
            continue
        n = _samples(float(np.max(np.abs(b - a))) / JOINT_STEP_RAD)
        u = np.linspace(0.0, 1.0, n)
        qs = a + u[:, None] * (b - a)
        out.append(_dense(kin, qs, motion.tool, owner, (done + u * seg_len) / total))
        done += seg_len
    return out


def _slerp_poses(t0: np.ndarray, t1: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Orientations from t0 to t1 by slerp at fractions u (positions left zero): scipy's Slerp's rotations (the
    relative rotation's rotation vector scaled by u), by Rodrigues' formula in numpy (a tenth of Slerp's time: it
    builds several Rotation objects a path; the same rotations to about 1e-15, tests/motion/test_path_rotations.py)."""
    r0 = t0[:3, :3]
    axis, angle = _axis_angle(r0.T @ t1[:3, :3])
    k = np.array(((0.0, -axis[2], axis[1]), (axis[2], 0.0, -axis[0]), (-axis[1], axis[0], 0.0)))
    th = u * angle
    turns = np.eye(3) + np.sin(th)[:, None, None] * k + (1.0 - np.cos(th))[:, None, None] * (k @ k)
    out = np.tile(np.eye(4), (len(u), 1, 1))
    out[:, :3, :3] = r0 @ turns
    return out


def _axis_angle(r: np.ndarray) -> tuple[np.ndarray, float]:
    """Unit axis and angle in [0, pi] of a rotation matrix, through its quaternion (Shepperd's choice of the largest
    component, as scipy's Rotation.from_matrix: exact near pi too); the axis is x for no rotation."""
    tr = float(r[0, 0] + r[1, 1] + r[2, 2])
    diag = (float(r[0, 0]), float(r[1, 1]), float(r[2, 2]))
    i = max(range(3), key=lambda j: diag[j])
    if tr >= diag[i]:
        w = 0.5 * math.sqrt(1.0 + tr)
        v = np.array((r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1])) / (4.0 * w)
    else:
        j, k = (i + 1) % 3, (i + 2) % 3
        v = np.empty(3)
        v[i] = 0.5 * math.sqrt(1.0 + 2.0 * diag[i] - tr)
        v[j] = (r[j, i] + r[i, j]) / (4.0 * v[i])
        v[k] = (r[k, i] + r[i, k]) / (4.0 * v[i])
        w = (r[k, j] - r[j, k]) / (4.0 * v[i])
    if w < 0.0:
        v, w = -v, -w
    norm = math.sqrt(float(v @ v))
    if norm == 0.0:
        return np.array((1.0, 0.0, 0.0)), 0.0
    return v / norm, 2.0 * math.atan2(norm, w)


def _rotation_angle(t0: np.ndarray, t1: np.ndarray) -> float:
    return _axis_angle(t0[:3, :3].T @ t1[:3, :3])[1]


def line_poses(t0: np.ndarray, t1: np.ndarray) -> np.ndarray:
    """TCP poses along a straight line: position linear, orientation by slerp."""
    dist = float(np.linalg.norm(t1[:3, 3] - t0[:3, 3]))
    n = _samples(max(dist / CART_STEP_M, _rotation_angle(t0, t1) / CART_STEP_RAD))
    u = np.linspace(0.0, 1.0, n)
    poses = _slerp_poses(t0, t1, u)
    poses[:, :3, 3] = t0[:3, 3] + u[:, None] * (t1[:3, 3] - t0[:3, 3])
    return poses


def circle_poses(t0: np.ndarray, via: np.ndarray, t1: np.ndarray) -> np.ndarray:
    """TCP poses on the circle through start, via and end; orientation slerped from start to end."""
    p0, p1, p2 = t0[:3, 3], via[:3, 3], t1[:3, 3]
    a, b = p1 - p0, p2 - p0
    normal = np.cross(a, b)
    nn = float(normal @ normal)
    if nn < 1e-12 or min(np.linalg.norm(a), np.linalg.norm(b), np.linalg.norm(p2 - p1)) < 1e-6:
        raise PlanningError("circular motion: start, via and end are (nearly) on one line or coincide; no circle passes through them")
    center = p0 + (float(a @ a) * np.cross(b, normal) + float(b @ b) * np.cross(normal, a)) / (2.0 * nn)
    radius = float(np.linalg.norm(p0 - center))
    e1 = (p0 - center) / radius
    e2 = np.cross(normal / math.sqrt(nn), e1)

    def angle(p: np.ndarray) -> float:
        return math.atan2(float((p - center) @ e2), float((p - center) @ e1)) % (2.0 * math.pi)

    sweep = angle(p2)  # p0 -> p1 -> p2 turns positively about `normal`, so the via lies in (0, sweep)
    n = _samples(max(radius * sweep / CART_STEP_M, _rotation_angle(t0, t1) / CART_STEP_RAD))
    u = np.linspace(0.0, 1.0, n)
    th = u * sweep
    poses = _slerp_poses(t0, t1, u)
    poses[:, :3, 3] = center + radius * (np.cos(th)[:, None] * e1 + np.sin(th)[:, None] * e2)
    poses[-1, :3, 3] = p2
    return poses


def cartesian_path(kin: Kinematics, q_start: np.ndarray, motion: CartesianMotion, owner: int) -> DensePath | None:
    """Joint samples of an LMOVE, CMOVE or Cartesian MOVE; None for a zero-length move."""
    t0 = kin.fk(q_start, motion.tool)
    t1 = motion.target.matrix()
    what = {"linear": "linear motion", "circular": "circular motion", "joint": "joint motion"}[motion.kind]
    if motion.kind == "joint":
        q1 = kin.ik(t1, q_start, motion.tool, what="joint motion target")
        segs = joint_segments(kin, q_start, JointMotion(tuple(q1), tool=motion.tool), owner)
        return segs[0] if segs else None
    if np.linalg.norm(t1[:3, 3] - t0[:3, 3]) < 1e-7 and _rotation_angle(t0, t1) < 1e-7:
        return None
    if motion.kind == "linear":
        poses = line_poses(t0, t1)
    else:
        assert motion.via is not None
        poses = circle_poses(t0, motion.via.matrix(), t1)
    try:
        qs = kin.ik_along(poses, q_start, motion.tool, what)
    except (Unreachable, JointLimit):
        kin.ik(t1, q_start, motion.tool, what=f"{what} target")  # a bad target itself is the clearer message
        raise
    return DensePath(qs, poses[:, :3, 3].copy(), np.full(len(qs), owner, dtype=int), np.linspace(0.0, 1.0, len(qs)))


def function_path(kin: Kinematics, q_start: np.ndarray, motion: FunctionMotion, owner: int, samples: int = 121) -> DensePath:
    """Joint samples of a function-space path (components functions of s); the path must start at the TCP."""
    u = np.linspace(0.0, 1.0, samples)
    poses = np.stack([motion.pose_at(float(x)) for x in u])
    here = kin.fk(q_start, motion.tool)
    gap = float(np.linalg.norm(poses[0, :3, 3] - here[:3, 3]))
    if gap > 1e-3 or _rotation_angle(poses[0], here) > 1e-3:
        raise PlanningError(
            f"function motion: its value at s=0 is {1000 * gap:.1f} mm away from where the TCP is; "
            "move to the start of the path first"
        )
    poses[0] = here
    qs = kin.ik_along(poses, q_start, motion.tool, "function motion")
    return DensePath(qs, poses[:, :3, 3].copy(), np.full(len(qs), owner, dtype=int), u)
