"""A copy of a cell's compiled model that places its geoms and flange at given joint positions (another process, the
3D view's, draws a run from the positions alone)."""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np

from orc_rpl.plant.shapes import Frames, Poses, Shape, geom_frames, geom_poses, model_shapes
from orc_rpl.plant.sim import site_pose


def live_qpos(cell: Any) -> np.ndarray:
    """MuJoCo's joint positions of the running cell, as a live view (read it, never write it; valid while the cell is)."""
    return cell._data.qpos  # type: ignore[no-any-return]


class CellPoser:
    """Places every geom and the flange of a cell at stored joint positions (MuJoCo's qpos); picklable (the model
    travels as MuJoCo's own binary form), so a process of its own can draw the cell and do the forward kinematics.
    It remembers where the cell stood when it was made (`qpos`)."""

    def __init__(self, cell: Any) -> None:
        self.model = cell._model
        self.flange_site: int = int(cell._flange_site)
        self.nq: int = int(self.model.nq)
        self.qpos: np.ndarray = live_qpos(cell).copy()
        self._data: Any = None

    def __getstate__(self) -> dict[str, Any]:
        return {"model": self.model, "flange_site": self.flange_site, "nq": self.nq, "qpos": self.qpos}

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state, _data=None)

    def shapes(self) -> tuple[Shape, ...]:
        """The cell's visible geoms (plant.shapes.cell_shapes of the cell this poser was made from)."""
        return model_shapes(self.model)

    def poses(self, qpos: np.ndarray) -> Poses:
        """Every geom's pose at `qpos` (plant.shapes.cell_poses of the cell standing there)."""
        self.flange(qpos)
        return geom_poses(self.model, self._data)

    def place(self, qpos: np.ndarray, time_s: float = 0.0) -> tuple[Frames, np.ndarray]:
        """Every geom's pose (MuJoCo's arrays, copied) and the flange's (4x4, world) at `qpos`."""
        flange = self.flange(qpos)
        return geom_frames(self._data, time_s), flange

    def flange(self, qpos: np.ndarray) -> np.ndarray:
        """The flange's pose (4x4, world) at `qpos` (for the trace's points this is all that is needed)."""
        if self._data is None:
            self._data = mujoco.MjData(self.model)
        self._data.qpos[:] = qpos
        mujoco.mj_kinematics(self.model, self._data)
        return site_pose(self._data, self.flange_site)
