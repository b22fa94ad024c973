"""Clearance: the nearest approach between a robot's moving links and the fixed objects of a compiled MuJoCo cell."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from orc_rpl.plant.cell import ROBOT_PREFIX, build_spec, default_cell
from orc_rpl.plant.gl import import_mujoco

mujoco = import_mujoco()

#: Pairs farther apart than this are not measured exactly (their clearance is "more than this").
DISTMAX_M = 0.5

#: Samples of a recording measured per second of simulated time (the recording itself is at the motion rate).
REPLAY_RATE_HZ = 50.0


@dataclass(frozen=True, slots=True)
class Approach:
    """The nearest approach at one instant: a negative distance is a penetration (a collision)."""

    distance_m: float
    robot_geom: str
    obstacle_geom: str
    time_s: float = 0.0


def _name(model: Any, geom: int) -> str:
    name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, geom)
    body = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, int(model.geom_bodyid[geom])) or "world"
    return name or f"{body} geom {geom}"


class ClearanceMeter:
    """Distances from the geoms of one robot's moving bodies to every fixed geom outside the robot.

    Works on any compiled model: the robot is the body tree rooted at `robot_root_body`; obstacles are the geoms of
    bodies welded to the world outside that tree; planes (the floor) are left out. Contact flags are ignored: the
    scene may have contacts off, distances are geometric. A broad phase on bounding spheres skips the pairs that
    cannot beat the nearest one found so far; the rest go to `mj_geomDistance`.
    """

    def __init__(self, model: Any, data: Any, robot_root_body: int, distmax_m: float = DISTMAX_M) -> None:
        self.model, self.data, self.distmax_m = model, data, distmax_m
        root, weld, body_of = model.body_rootid, model.body_weldid, model.geom_bodyid
        robot = [g for g in range(model.ngeom) if root[body_of[g]] == robot_root_body and weld[body_of[g]] != 0]
        fixed = [g for g in range(model.ngeom) if root[body_of[g]] != robot_root_body and weld[body_of[g]] == 0
                 and model.geom_type[g] != mujoco.mjtGeom.mjGEOM_PLANE]
        self.pairs = np.array([(a, b) for a in robot for b in fixed], dtype=int).reshape(-1, 2)

    def measure(self, time_s: float = 0.0) -> Approach | None:
        """The nearest pair now (the data's kinematics must be current); None when none is within distmax_m."""
        m, d = self.model, self.data
        if len(self.pairs) == 0:
            return None
        a, b = self.pairs[:, 0], self.pairs[:, 1]
        gaps = np.linalg.norm(d.geom_xpos[a] - d.geom_xpos[b], axis=1) - m.geom_rbound[a] - m.geom_rbound[b]
        best, which = self.distmax_m, -1
        for i in np.argsort(gaps):  # nearest spheres first, so the cut below skips most pairs
            if gaps[i] >= best:
                break
            distance = mujoco.mj_geomDistance(m, d, int(a[i]), int(b[i]), best, None)
            if distance < best:
                best, which = distance, int(i)
        if which < 0:
            return None
        return Approach(float(best), _name(m, int(a[which])), _name(m, int(b[which])), time_s)


def robot_root(model: Any, prefix: str = ROBOT_PREFIX) -> int:
    """The root body of the robot whose bodies are named with `prefix`."""
    for body in range(model.nbody):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, body) or ""
        if name.startswith(prefix):
            return int(model.body_rootid[body])
    raise ValueError(f"no body named {prefix}... in the model")


def nearest_along(model: Any, data: Any, joints: Sequence[int], time_s: np.ndarray, q: np.ndarray,
                  rate_hz: float = REPLAY_RATE_HZ, robot_root_body: int | None = None) -> Approach | None:
    """The nearest approach over a recorded joint trajectory, sampled at `rate_hz` (and its last sample)."""
    meter = ClearanceMeter(model, data, robot_root(model) if robot_root_body is None else robot_root_body)
    if len(time_s) == 0:
        return None
    step = max(1, int(round(1.0 / (rate_hz * max(float(np.median(np.diff(time_s))) if len(time_s) > 1 else 1.0, 1e-9)))))
    samples = list(range(0, len(time_s), step))
    if samples[-1] != len(time_s) - 1:
        samples.append(len(time_s) - 1)
    qpos = [int(model.jnt_qposadr[j]) for j in joints]
    nearest: Approach | None = None
    for i in samples:
        data.qpos[qpos] = q[i, : len(qpos)]
        mujoco.mj_kinematics(model, data)
        approach = meter.measure(float(time_s[i]))
        if approach is not None and (nearest is None or approach.distance_m < nearest.distance_m):
            nearest = approach
    return nearest


def nearest_in_default_cell(robot: str, time_s: np.ndarray, q: np.ndarray,
                            rate_hz: float = REPLAY_RATE_HZ) -> Approach | None:
    """A recorded run replayed in the default cell (the scene `orc run` builds when no world scene is given)."""
    model = build_spec(default_cell(robot)).compile()
    data = mujoco.MjData(model)
    joints = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, f"{ROBOT_PREFIX}j{i + 1}") for i in range(q.shape[1])]
    return nearest_along(model, data, [j for j in joints if j >= 0], time_s, q, rate_hz)
