"""Clearance: the nearest approach between a robot's moving links and the fixed objects of a compiled MuJoCo cell."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from orc_rpl.plant.cell import ROBOT_PREFIX
from orc_rpl.plant.gl import import_mujoco
from orc_rpl.plant.sim import SimCell

mujoco = import_mujoco()

#: Pairs farther apart than this are not measured exactly (their clearance is "more than this").
DISTMAX_M = 0.5

#: A followed run's nearest approach is exact to this, or to TOLERANCE_FRACTION of it when that is larger: a sample
#: is measured exactly unless the robot cannot have come nearer than that since the last exact measurement.
TOLERANCE_M = 0.0005
TOLERANCE_FRACTION = 0.02


@dataclass(frozen=True, slots=True)
class Approach:
    """The nearest approach at one instant: a negative distance is a penetration (a collision)."""

    distance_m: float
    robot_geom: str
    obstacle_geom: str
    time_s: float = 0.0
    robot_body: str = ""            #: the robot's link (or the tool on its flange) that came nearest, for people
    obstacle: str = ""              #: the object of the cell it came nearest to (a world object's name)


def _name(model: Any, geom: int) -> str:
    name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, geom)
    body = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, int(model.geom_bodyid[geom])) or "world"
    return name or f"{body} geom {geom}"


def _body(model: Any, geom: int) -> str:
    """A geom's body for people: a named geom on the world or the payload (a world object, a tool) by its own name,
    else its body's name without the robot prefix (a link)."""
    body = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, int(model.geom_bodyid[geom])) or "world"
    name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, geom)
    if name and body in ("world", "payload"):
        return name
    return body.removeprefix(ROBOT_PREFIX)


class ClearanceMeter:
    """Distances from the geoms of one robot's moving bodies to every fixed geom outside the robot.

    Works on any compiled model: the robot is the body tree rooted at `robot_root_body`; obstacles are the geoms of
    bodies welded to the world outside that tree; planes (the floor) are left out. Contact flags are ignored: the
    scene may have contacts off, distances are geometric. A broad phase on bounding spheres skips the pairs that
    cannot beat the nearest one found so far; the rest go to `mj_geomDistance`.
    """

    def __init__(self, model: Any, data: Any, robot_root_body: int, distmax_m: float = DISTMAX_M,
                 ignored: frozenset[int] = frozenset()) -> None:
        """`ignored`: geoms that are no obstacle (what the robot works on: a casting it grinds)."""
        self.model, self.data, self.distmax_m = model, data, distmax_m
        root, weld, body_of = model.body_rootid, model.body_weldid, model.geom_bodyid
        robot = [g for g in range(model.ngeom) if root[body_of[g]] == robot_root_body and weld[body_of[g]] != 0]
        fixed = [g for g in range(model.ngeom) if root[body_of[g]] != robot_root_body and weld[body_of[g]] == 0
                 and model.geom_type[g] != mujoco.mjtGeom.mjGEOM_PLANE and g not in ignored]
        self.robot_geoms = np.array(robot, dtype=int)
        self._names: dict[int, tuple[str, str]] = {}  #: geom -> (name, body for people), looked up once
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
        (near, near_body), (far, far_body) = self._named(int(a[which])), self._named(int(b[which]))
        return Approach(float(best), near, far, time_s, near_body, far_body)

    def _named(self, geom: int) -> tuple[str, str]:
        names = self._names.get(geom)
        if names is None:
            names = self._names[geom] = (_name(self.model, geom), _body(self.model, geom))
        return names


def robot_root(model: Any, prefix: str = ROBOT_PREFIX) -> int:
    """The root body of the robot whose bodies are named with `prefix`."""
    for body in range(model.nbody):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, body) or ""
        if name.startswith(prefix):
            return int(model.body_rootid[body])
    raise ValueError(f"no body named {prefix}... in the model")


class RunClearance:
    """The nearest approach per motion, followed while a simulated cell runs: on the cell's own compiled model (the
    default cell, or the one made from the run's world, tools on the flange and payload included), at the robot's
    true joint angles of the moment, the work excluded (the casting a tool grinds is no obstacle).

    `sample(key, time_s)` is called every motion cycle while a motion runs (`key`: which motion). It measures
    exactly (ClearanceMeter on a private MjData: the run itself is never touched) unless the robot cannot have come
    nearer than the motion's nearest so far less the tolerance: every point of the robot moved at most
    sum(|dq_j| * reach_j) since the last exact measurement, `reach_j` bounding the distance of any robot point
    from joint j's axis. So each motion's nearest approach is exact, to the tolerance, at the motion cycles.
    """

    def __init__(self, cell: SimCell, distmax_m: float = DISTMAX_M) -> None:
        m = cell._model  # the plant room's own cell: its compiled model is shared, never its data
        self.model, self.data, self.source = m, mujoco.MjData(m), cell._data
        root = robot_root(m)
        self.meter = ClearanceMeter(m, self.data, root, distmax_m, frozenset(cell._work_geoms))
        # every joint of the robot's tree: a realistic plant adds a gear joint beside each of the robot's own
        joints = [j for j in range(m.njnt) if m.body_rootid[m.jnt_bodyid[j]] == root]
        self._qpos = np.array([m.jnt_qposadr[j] for j in joints], dtype=int)
        self.reach_m = _reach(m, joints, self.meter.robot_geoms)
        self.nearest: dict[Any, Approach | None] = {}   #: per motion key: its nearest approach (None: > distmax)
        self.measured, self.samples = 0, 0
        self._key: Any = None
        self._last_q = np.zeros(len(self._qpos))
        self._last_m = distmax_m                         #: the distance measured exactly last (distmax: farther)

    def sample(self, key: Any, time_s: float) -> None:
        """Follow the motion `key` at the cell's present state."""
        self.samples += 1
        q = self.source.qpos[self._qpos]
        best = self.nearest.get(key, None)
        best_m = self.meter.distmax_m if best is None else best.distance_m
        if key == self._key:
            moved_m = float(np.abs(q - self._last_q) @ self.reach_m)
            if self._last_m - moved_m >= best_m - max(TOLERANCE_M, TOLERANCE_FRACTION * abs(best_m)):
                return  # it cannot have come nearer than its nearest so far, less the tolerance
        self._key = key
        self.data.qpos[:] = self.source.qpos
        mujoco.mj_kinematics(self.model, self.data)
        approach = self.meter.measure(time_s)
        self.measured += 1
        self._last_q, self._last_m = q.copy(), self.meter.distmax_m if approach is None else approach.distance_m
        if key not in self.nearest or (approach is not None and approach.distance_m < best_m):
            self.nearest[key] = approach


def _reach(model: Any, joints: list[int], robot_geoms: np.ndarray) -> np.ndarray:
    """Per joint of the robot: how far any point of a robot geom moves per unit of that joint at most (m/rad for a
    hinge: a bound on the point's distance from its axis; 1 for a slide; infinite for a ball or free joint, whose
    samples are then always measured). The bound is the length of the body tree from the joint to the geom plus
    the geom's bounding radius, which holds in every configuration."""
    def chain_m(body: int, up_to: int) -> float:
        length = 0.0
        while body != up_to and body > 0:
            length += float(np.linalg.norm(model.body_pos[body]))
            body = int(model.body_parentid[body])
        return length if body == up_to else -1.0  # -1: the geom is not carried by this joint's body

    reach = np.zeros(len(joints))
    for i, joint in enumerate(joints):
        if model.jnt_type[joint] == mujoco.mjtJoint.mjJNT_SLIDE:
            reach[i] = 1.0
            continue
        if model.jnt_type[joint] != mujoco.mjtJoint.mjJNT_HINGE:
            reach[i] = np.inf
            continue
        body = int(model.jnt_bodyid[joint])
        for geom in robot_geoms:
            length = chain_m(int(model.geom_bodyid[geom]), body)
            if length >= 0.0:
                offset = float(np.linalg.norm(model.geom_pos[geom])) + float(model.geom_rbound[geom])
                reach[i] = max(reach[i], length + offset + float(np.linalg.norm(model.jnt_pos[joint])))
    return reach
