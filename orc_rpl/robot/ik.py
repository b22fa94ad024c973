"""The robot room's inverse kinematics: damped least squares inside the joint ranges, nearest solution to the seed."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from orc_rpl.robot.model import ArmModel
from orc_rpl.errors import Unreachable

_TWO_PI = 2.0 * math.pi


@dataclass(frozen=True, slots=True)
class IkSettings:
    """Tuning of the solver; the defaults reach 1e-10 m / rad in a few dozen iterations from a nearby seed."""

    tolerance: float = 1e-10           #: m for position, rad for rotation
    max_iterations: int = 150          #: per start
    max_step_rad: float = 0.4          #: largest joint change per iteration (keeps DLS on one branch)
    restarts: int = 10                 #: deterministic extra starts when the seed's answer is not near it
    near_seed_rad: float = 0.6         #: a seed answer within this (max-norm) distance is taken at once
    #: Arms with fewer than six axes: the orientation the target asks may be one the arm cannot take.
    #: The position is reached exactly and the orientation as near as the arm can (least squares);
    #: a remaining angle error up to this is accepted, a larger one makes the target Unreachable.
    reduced_angle_tolerance_rad: float = math.radians(0.5)
    reduced_rotation_weight_m: float = 0.05  #: weight of a radian against a metre in the reduced fit


def rotation_error(r_target: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Rotation vector (world frame) that turns r into r_target: log(r_target r^T)."""
    e = r_target @ r.T
    cos_angle = max(-1.0, min(1.0, 0.5 * (e[0, 0] + e[1, 1] + e[2, 2] - 1.0)))
    vee = np.array([e[2, 1] - e[1, 2], e[0, 2] - e[2, 0], e[1, 0] - e[0, 1]])
    angle = math.acos(cos_angle)
    if angle < 1e-6:
        return 0.5 * vee
    if math.pi - angle > 1e-6:
        return vee * (angle / (2.0 * math.sin(angle)))
    # Near a half turn: the axis comes from the symmetric part, its sign from vee.
    sym = 0.5 * (e + e.T) - cos_angle * np.eye(3)
    k = int(np.argmax(np.diag(sym)))
    axis = sym[:, k] / math.sqrt(max(sym[k, k], 1e-300))
    if axis @ vee < 0.0:
        axis = -axis
    return axis * angle


def _pose_error(target: np.ndarray, t: np.ndarray) -> np.ndarray:
    return np.concatenate((target[:3, 3] - t[:3, 3], rotation_error(target[:3, :3], t[:3, :3])))


def _descend(model: ArmModel, target: np.ndarray, q0: np.ndarray, tool: np.ndarray | None,
             settings: IkSettings) -> tuple[np.ndarray, np.ndarray]:
    """Levenberg-Marquardt steps from q0, clamped to the joint ranges; returns (q, final error 6-vector)."""
    if model.n_joints < 6:
        return _descend_reduced(model, target, q0, tool, settings)
    lo, hi = model.q_min, model.q_max
    q = np.clip(q0, lo, hi)
    t, jac = model._fk_jacobian(q, tool)
    err = _pose_error(target, t)
    cost = float(err @ err)
    damping = 1e-4
    eye = np.eye(6)
    stalls = 0
    for _ in range(settings.max_iterations):
        if abs(err[:3]).max() < settings.tolerance and abs(err[3:]).max() < settings.tolerance:
            break
        j = jac.copy()
        # Joints resting on a limit and pushed outwards drop out of the step (an active set).
        for _pass in range(3):
            dq = j.T @ np.linalg.solve(j @ j.T + damping * eye, err)
            largest = abs(dq).max()
            if largest > settings.max_step_rad:
                dq *= settings.max_step_rad / largest
            blocked = ((q + dq < lo) & (dq < 0.0)) | ((q + dq > hi) & (dq > 0.0))
            if not blocked.any():
                break
            j[:, blocked] = 0.0
        q_new = np.clip(q + dq, lo, hi)
        t_new, jac_new = model._fk_jacobian(q_new, tool)
        err_new = _pose_error(target, t_new)
        cost_new = float(err_new @ err_new)
        if cost_new < cost:
            # A local minimum off the target (out of reach) only creeps: give up after a few such steps.
            stalls = stalls + 1 if cost_new > cost * (1.0 - 1e-6) and cost_new > settings.tolerance**2 else 0
            if stalls > 5:
                break
            q, jac, err, cost = q_new, jac_new, err_new, cost_new
            damping = max(damping * 0.3, 1e-12)
        else:
            damping *= 10.0
            if damping > 1e3:
                break
    return q, err


def _descend_reduced(model: ArmModel, target: np.ndarray, q0: np.ndarray, tool: np.ndarray | None,
                     settings: IkSettings) -> tuple[np.ndarray, np.ndarray]:
    """Fewer than six axes: a weighted least-squares fit of the pose, then the position alone made exact.

    The fit finds the orientation nearest to the target's that the arm can take; the second stage
    moves the joints the least that closes the position error (minimum-norm Gauss-Newton steps on the
    three position rows), so a target's position is never traded for its orientation.
    """
    lo, hi = model.q_min, model.q_max
    weights = np.array([1.0, 1.0, 1.0] + [settings.reduced_rotation_weight_m] * 3)
    q = np.clip(q0, lo, hi)
    damping = 1e-6
    t, jac = model._fk_jacobian(q, tool)
    err = _pose_error(target, t) * weights
    cost = float(err @ err)
    for _ in range(settings.max_iterations):
        j = jac * weights[:, None]
        dq = np.linalg.solve(j.T @ j + damping * np.eye(model.n_joints), j.T @ err)
        largest = abs(dq).max()
        if largest > settings.max_step_rad:
            dq *= settings.max_step_rad / largest
        q_new = np.clip(q + dq, lo, hi)
        t_new, jac_new = model._fk_jacobian(q_new, tool)
        err_new = _pose_error(target, t_new) * weights
        cost_new = float(err_new @ err_new)
        if cost_new < cost:
            done = cost - cost_new < 1e-14 * max(cost, 1e-30) or abs(q_new - q).max() < 1e-13
            q, jac, err, cost = q_new, jac_new, err_new, cost_new
            damping = max(damping * 0.3, 1e-12)
            if done:
                break
        else:
            damping *= 10.0
            if damping > 1e3:
                break
    t, jac = model._fk_jacobian(q, tool)
    e_p = target[:3, 3] - t[:3, 3]
    for _ in range(20):  # the position made exact from the fit's joint values (steps that help only)
        if abs(e_p).max() < settings.tolerance:
            break
        jp = jac[:3]
        q_new = np.clip(q + jp.T @ np.linalg.solve(jp @ jp.T + 1e-12 * np.eye(3), e_p), lo, hi)
        t_new, jac_new = model._fk_jacobian(q_new, tool)
        e_new = target[:3, 3] - t_new[:3, 3]
        if float(e_new @ e_new) >= float(e_p @ e_p):
            break
        q, t, jac, e_p = q_new, t_new, jac_new, e_new
    return q, _pose_error(target, t)


def _nearest_turn(model: ArmModel, q: np.ndarray, seed: np.ndarray) -> np.ndarray:
    """Shift joints by whole turns towards the seed where the range allows (j6 of +-400 deg, for example)."""
    q = q.copy()
    for i in range(model.n_joints):
        turns = round((seed[i] - q[i]) / _TWO_PI)
        if turns:
            shifted = q[i] + turns * _TWO_PI
            if model.q_min[i] <= shifted <= model.q_max[i]:
                q[i] = shifted
    return q


def _restart_seeds(model: ArmModel, target: np.ndarray, seed: np.ndarray, count: int) -> list[np.ndarray]:
    """Deterministic starts: the seed turned towards the target, its wrist flipped, home, then fixed draws."""
    seeds: list[np.ndarray] = []
    heading = math.atan2(target[1, 3], target[0, 3])
    for base_angle in (heading, heading + math.pi, heading - math.pi):
        s = seed.copy()
        s[0] = base_angle
        seeds.append(s)
    if model.n_joints == 6:
        flipped = seed.copy()
        flipped[3] += math.pi if flipped[3] < 0.0 else -math.pi
        flipped[4] = -flipped[4]
        flipped[5] += math.pi if flipped[5] < 0.0 else -math.pi
        seeds.append(flipped)
    seeds.append(model.home_q.copy())
    rng = np.random.default_rng(20240601)  # fixed: the same call always gives the same answer
    for _ in range(count):
        s = rng.uniform(model.q_min, model.q_max)
        s[0] = heading
        seeds.append(s)
    return [np.clip(s, model.q_min, model.q_max) for s in seeds]


def solve_ik(model: ArmModel, target: Any, q_seed: Any, tool: Any = None,
             settings: IkSettings = IkSettings()) -> np.ndarray:
    """Joint angles that put the TCP on `target` (4x4, base frame), inside the ranges and nearest to `q_seed`.

    Raises Unreachable, with the target's position and by how much the best attempt misses it.
    """
    target = model.transform(target, "IK target")
    seed = model.vector(q_seed, "q_seed")
    t_tool = None if tool is None else model.transform(tool)

    best_miss: tuple[float, float] = (math.inf, math.inf)
    rot_tolerance = settings.tolerance * 10 if model.n_joints >= 6 else settings.reduced_angle_tolerance_rad
    solutions: list[np.ndarray] = []
    #: fewer than six axes: how far each solution's orientation is from the target's (exact ones are preferred)
    rot_misses: dict[int, float] = {}

    def attempt(start: np.ndarray) -> np.ndarray | None:
        nonlocal best_miss
        q, err = _descend(model, target, start, t_tool, settings)
        pos_miss, rot_miss = float(np.linalg.norm(err[:3])), float(np.linalg.norm(err[3:]))
        if pos_miss < settings.tolerance * 10 and rot_miss < rot_tolerance:
            q = _nearest_turn(model, q, seed)
            rot_misses[id(q)] = rot_miss
            return q
        if pos_miss + rot_miss < sum(best_miss):
            best_miss = (pos_miss, rot_miss)
        return None

    def exact(q: np.ndarray) -> bool:
        return model.n_joints >= 6 or rot_misses[id(q)] < settings.tolerance * 10

    first = attempt(seed)
    if first is not None and abs(first - seed).max() <= settings.near_seed_rad and exact(first):
        return first
    if first is not None:
        solutions.append(first)
    for start in _restart_seeds(model, target, seed, settings.restarts):
        q = attempt(start)
        if q is not None:
            solutions.append(q)
    if solutions:
        # (with six axes every solution is exact: nearest to the seed, as always)
        return min(solutions, key=lambda s: (not exact(s), float(np.sum((s - seed) ** 2))))

    p = target[:3, 3]
    tool_text = "" if t_tool is None else f" with a tool {1000 * np.linalg.norm(t_tool[:3, 3]):.0f} mm long"
    raise Unreachable(
        f"target ({p[0]:.4f}, {p[1]:.4f}, {p[2]:.4f}) m, {np.linalg.norm(p):.3f} m from the base, "
        f"is out of reach of {model.name}{tool_text}: the nearest configuration inside the joint ranges "
        f"misses it by {1000 * best_miss[0]:.1f} mm and {math.degrees(best_miss[1]):.2f} deg"
    )
