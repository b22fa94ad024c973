"""The plant room's geometry for viewers: the compiled cell's visible geoms as plain values, and where they are now."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from orc_rpl.plant.sim import SimCell, mujoco

#: MuJoCo geom types by the names viewers draw them with.
KINDS: dict[int, str] = {
    int(mujoco.mjtGeom.mjGEOM_PLANE): "plane",
    int(mujoco.mjtGeom.mjGEOM_SPHERE): "sphere",
    int(mujoco.mjtGeom.mjGEOM_CAPSULE): "capsule",
    int(mujoco.mjtGeom.mjGEOM_ELLIPSOID): "ellipsoid",
    int(mujoco.mjtGeom.mjGEOM_CYLINDER): "cylinder",
    int(mujoco.mjtGeom.mjGEOM_BOX): "box",
    int(mujoco.mjtGeom.mjGEOM_MESH): "mesh",
}

#: Geom groups 0-2 are drawn by MuJoCo's own viewer by default; higher groups hold collision-only shapes.
VISIBLE_GROUPS = 3


@dataclass(frozen=True)
class Shape:
    """One visible geom of the compiled cell, in its own frame (MuJoCo's sizes: half-extents, radii, half-lengths)."""

    index: int                                 #: the geom's index in the model (rows of `Poses`)
    name: str                                  #: the geom's name, or `geom<index>` when it has none
    body: str                                  #: the body it moves with (`world` for fixed geometry)
    kind: str                                  #: plane | sphere | capsule | ellipsoid | cylinder | box | mesh
    size_m: tuple[float, float, float]
    rgba: tuple[float, float, float, float]
    vertices_m: np.ndarray | None = field(default=None, compare=False)  #: mesh only: (N, 3)
    faces: np.ndarray | None = field(default=None, compare=False)       #: mesh only: (M, 3) vertex indices

    @property
    def moves(self) -> bool:
        """True for geoms on a moving body (the robot's links); fixed geometry is placed once."""
        return self.body != "world"


@dataclass(frozen=True)
class Poses:
    """Where every geom of the cell is at one instant: positions (n, 3) in m and orientations (n, 4) as w, x, y, z."""

    time_s: float
    position_m: np.ndarray
    wxyz: np.ndarray


@dataclass(frozen=True)
class Frames:
    """Where every geom is at one instant as MuJoCo keeps it: positions (n, 3) in m, rotation matrices (n, 3, 3)."""

    time_s: float
    position_m: np.ndarray
    rotation: np.ndarray


def cell_shapes(cell: SimCell) -> tuple[Shape, ...]:
    """The visible geoms of the cell as built (robot, fixed geometry, whatever the scene contains), in model order."""
    return model_shapes(cell._model)


def model_shapes(m: Any) -> tuple[Shape, ...]:
    """The visible geoms of a compiled MuJoCo model (a cell's, or a copy of it in another process), in model order."""
    shapes = []
    for i in range(m.ngeom):
        kind = KINDS.get(int(m.geom_type[i]))
        if kind is None or int(m.geom_group[i]) >= VISIBLE_GROUPS or float(m.geom_rgba[i][3]) <= 0.0:
            continue
        name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, i) or f"geom{i}"
        body = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, int(m.geom_bodyid[i])) or "world"
        vertices = faces = None
        if kind == "mesh":
            mesh = int(m.geom_dataid[i])
            v0, nv = int(m.mesh_vertadr[mesh]), int(m.mesh_vertnum[mesh])
            f0, nf = int(m.mesh_faceadr[mesh]), int(m.mesh_facenum[mesh])
            vertices = np.array(m.mesh_vert[v0:v0 + nv], dtype=np.float32)
            faces = np.array(m.mesh_face[f0:f0 + nf], dtype=np.int32)
        shapes.append(Shape(i, name, body, kind, tuple(float(s) for s in m.geom_size[i]),  # type: ignore[arg-type]
                            tuple(float(c) for c in m.geom_rgba[i]), vertices, faces))  # type: ignore[arg-type]
    return tuple(shapes)


def cell_poses(cell: SimCell) -> Poses:
    """Every geom's world pose now (after the last step's kinematics); copies, safe to hand to another thread."""
    return geom_poses(cell._model, cell._data)


def geom_poses(m: Any, d: Any) -> Poses:
    """Every geom's world pose in MuJoCo data `d` of model `m` (after its kinematics), as copies."""
    wxyz = np.empty((m.ngeom, 4))
    for i in range(m.ngeom):
        mujoco.mju_mat2Quat(wxyz[i], d.geom_xmat[i])
    return Poses(float(d.time), d.geom_xpos.copy(), wxyz)


def cell_frames(cell: SimCell) -> Frames:
    """Every geom's world pose now, as copies of MuJoCo's arrays: cheap enough to take in a motion cycle (a viewer
    turns the matrices into quaternions on its own thread)."""
    return geom_frames(cell._data, float(cell._data.time))


def geom_frames(d: Any, time_s: float) -> Frames:
    """Every geom's world pose in MuJoCo data `d` (after its kinematics), as copies of its arrays."""
    return Frames(time_s, d.geom_xpos.copy(), d.geom_xmat.reshape(-1, 3, 3).copy())
