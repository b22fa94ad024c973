"""Acquire services (thesis 5.2): kinematics, dynamics at a configuration, simulation of moves, and PathLeft."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from orc_rpl.errors import UsageError
from orc_rpl.motion.backend import KinematicBackend
from orc_rpl.motion.handle import MoveHandle
from orc_rpl.motion.specs import DEFAULT_PARAMS, CartesianMotion, FunctionMotion, JointMotion, Motion, Params
from orc_rpl.world.pose import Pose

if TYPE_CHECKING:
    from orc_rpl.motion.layer import MotionLayer


@dataclass(frozen=True, slots=True)
class Dynamics:
    """The arm's dynamics at one configuration."""

    torque_nm: np.ndarray    #: torque for the given q, qd, qdd (gravity alone at rest)
    mass_matrix: np.ndarray  #: joint-space inertia
    gravity_nm: np.ndarray   #: torque holding q against gravity


@dataclass(frozen=True, slots=True)
class Simulation:
    """A predicted run of moves: references every motion cycle, without moving the robot."""

    duration_s: float
    time_s: np.ndarray   #: (K,)
    q: np.ndarray        #: (K, n) joint references
    qd: np.ndarray       #: (K, n)
    move_times_s: tuple[float, ...]  #: each move's end time, from the start of the simulation


def dynamics(layer: MotionLayer, q: np.ndarray, qd: np.ndarray | None = None, qdd: np.ndarray | None = None,
             load_kg: float = 0.0) -> Dynamics:
    """Torque, inertia and gravity at q (the same model the planner uses)."""
    arm = layer.kin.arm
    q = np.asarray(q, dtype=float)
    z = np.zeros_like(q)
    qd = z if qd is None else np.asarray(qd, dtype=float)
    qdd = z if qdd is None else np.asarray(qdd, dtype=float)
    return Dynamics(np.array(arm.inverse_dynamics(q, qd, qdd, load_kg)), np.array(arm.mass_matrix(q, load_kg)),
                    np.array(arm.inverse_dynamics(q, z, z, load_kg)))


def simulate(layer: MotionLayer, moves: Sequence[Motion | tuple[Motion, Params]], q_start: np.ndarray | None = None) -> Simulation:
    """Plan and run `moves` on a kinematic copy of the layer (blends included); the robot does not move."""
    start = layer._tail_q() if q_start is None else np.asarray(q_start, dtype=float)
    # a scratch layer of the caller's own class (not an import of layer.py, which imports this file)
    scratch = type(layer)(layer.kin, KinematicBackend(start, layer.backend.servo_period_s), layer.dt_s)
    scratch.smoothing_s = layer.smoothing_s   # moves from rest averaged as the layer's are (elastic gears): as long
    scratch.planner.gear_steps = layer.planner.gear_steps
    handles: list[MoveHandle] = []
    for item in moves:
        motion, params = item if isinstance(item, tuple) else (item, DEFAULT_PARAMS)
        handles.append(scratch.move(motion, params))
    t, q, qd = [0.0], [start.copy()], [np.zeros_like(start)]
    while not scratch.idle():
        scratch.tick()
        t.append(scratch.now_s())
        q.append(scratch.reference_q())
        qd.append(scratch._qd_ref.copy())
    ends = tuple(float(h.end_time_s) if h.end_time_s is not None else 0.0 for h in handles)
    return Simulation(t[-1], np.array(t), np.array(q), np.array(qd), ends)


def path_left(what: MoveHandle | Motion, s: float) -> Motion:
    """The rest of a path from path coordinate s (PathLeft); a circle or via points need the move's handle."""
    if not 0.0 <= s <= 1.0:
        raise UsageError(f"path_left: s must be within 0..1, got {s}")
    handle = what if isinstance(what, MoveHandle) else None
    motion = handle.motion if handle is not None else what
    if isinstance(motion, FunctionMotion):
        if motion.variable != "s":
            raise UsageError("path_left: a function motion of time has no path to continue")

        def rest(c):  # type: ignore[no-untyped-def]
            return (lambda u: c(s + (1.0 - s) * u)) if callable(c) else c

        return FunctionMotion(rest(motion.x), rest(motion.y), rest(motion.z), rest(motion.a), rest(motion.b),
                              rest(motion.c), "s", 0.0, motion.tool)
    if isinstance(motion, CartesianMotion):
        if motion.kind != "circular":
            return motion  # from any point on a line (or before a joint move's target) the rest ends at the target
        if handle is None or handle.plan is None:
            raise UsageError("path_left of a circular motion needs its MoveHandle (the circle depends on its start)")
        dense = handle.plan.pieces[0]
        mid = s + 0.5 * (1.0 - s)
        p = dense.tcp[int(np.argmin(np.abs(dense.s - mid)))]
        return CartesianMotion(motion.target, "circular", Pose(float(p[0]), float(p[1]), float(p[2])), motion.tool)
    if isinstance(motion, JointMotion):
        if not motion.via_rad:
            return motion
        if handle is None or handle.plan is None:
            raise UsageError("path_left of a joint motion with via points needs its MoveHandle")
        corners = [handle.plan.start_q] + [np.array(v) for v in motion.via_rad] + [np.array(motion.target_rad)]
        lengths = np.cumsum([0.0] + [float(np.linalg.norm(b - a)) for a, b in zip(corners, corners[1:])])
        s_via = lengths[1:-1] / lengths[-1]
        left = tuple(v for v, sv in zip(motion.via_rad, s_via) if sv > s + 1e-9)
        return JointMotion(motion.target_rad, left, motion.tool)
    raise UsageError(f"path_left: not a motion: {type(motion).__name__}")
