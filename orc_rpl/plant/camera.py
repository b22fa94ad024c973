"""The plant room's film camera: offscreen pictures of the cell from a free camera aimed at the work (for videos)."""

from __future__ import annotations

from typing import Any

import numpy as np

from orc_rpl.errors import UsageError
from orc_rpl.plant.sim import SimCell, mujoco


def _no_gl(error: Exception) -> UsageError:
    return UsageError(
        f"cannot render the cell offscreen ({type(error).__name__}: {error}); "
        "set MUJOCO_GL=egl or MUJOCO_GL=osmesa (apt-get install libosmesa6) before starting")


class OffscreenCamera:
    """A MuJoCo renderer with a free camera: `aim()` once, then `picture()` each video frame (RGB, uint8)."""

    def __init__(self, cell: SimCell, width: int, height: int) -> None:
        model = cell._model
        # The offscreen buffer is fixed when the model is compiled; larger pictures cannot be made.
        limit = (int(model.vis.global_.offwidth), int(model.vis.global_.offheight))
        if width > limit[0] or height > limit[1]:
            raise UsageError(f"a picture of {width}x{height} is larger than the cell's offscreen buffer {limit[0]}x{limit[1]}")
        self._cell = cell
        try:
            self._renderer: Any = mujoco.Renderer(model, height, width)
        except Exception as error:  # no GL context
            raise _no_gl(error) from None
        self._camera = mujoco.MjvCamera()
        self._camera.type = mujoco.mjtCamera.mjCAMERA_FREE

    def aim(self, lookat_m: tuple[float, float, float], distance_m: float, azimuth_deg: float, elevation_deg: float) -> None:
        """Look at a point from a distance, turned azimuth about z and raised elevation (negative: from above)."""
        self._camera.lookat[:] = lookat_m
        self._camera.distance = distance_m
        self._camera.azimuth = azimuth_deg
        self._camera.elevation = elevation_deg

    def picture(self) -> np.ndarray:
        """The cell as it is now, seen from the camera: (height, width, 3) uint8."""
        try:
            self._renderer.update_scene(self._cell._data, camera=self._camera)
            flags = self._renderer.scene.flags
            # software GL: shadows and the floor's reflection cost four fifths of a frame
            flags[mujoco.mjtRndFlag.mjRND_SHADOW] = flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = False
            return self._renderer.render()
        except Exception as error:
            raise _no_gl(error) from None

    def close(self) -> None:
        """Free the GL context."""
        self._renderer.close()
