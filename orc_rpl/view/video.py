"""Videos of runs: the cell filmed offscreen at the simulated clock's real-time speed, captioned with the statement."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Any

import imageio.v2 as imageio
import numpy as np
from PIL import Image, ImageDraw, ImageFont

from orc_rpl.errors import UsageError
from orc_rpl.executive.executive import Executive
from orc_rpl.listeners import Listeners
from orc_rpl.plant.camera import OffscreenCamera
from orc_rpl.view.framing import Framing
from orc_rpl.view.live import sim_cell, statement_caption

FPS = 25
WIDTH, HEIGHT = 640, 480
CAPTION_PX = 18
#: Two frames are due at the same instant when their times differ by less than this (float rounding of the clock).
CLOCK_EPS_S = 1e-9


def frames_for(duration_s: float, fps: int = FPS) -> int:
    """How many frames a run of `duration_s` simulated seconds gives: one at 0 s, then one every 1/fps."""
    return int(np.floor(duration_s * fps + 1e-6)) + 1


class VideoRecorder:
    """Film a run: `monitor(robot)` listens to its motion cycles, `close()` at the end (also after a failure)."""

    def __init__(self, path: str | Path, executive: Executive, robot: Any, framing: Framing, fps: int = FPS,
                 size: tuple[int, int] = (WIDTH, HEIGHT)) -> None:
        cell = sim_cell(robot)
        if cell is None:
            raise UsageError("--video films the simulated cell; this robot has none")
        self.executive, self.robot, self.fps = executive, robot, fps
        self.frames = 0                                   #: frames written so far
        self._listening: Listeners[[]] = Listeners()          #: the tick listeners of the robot filmed
        self.camera = OffscreenCamera(cell, *size)
        self.camera.aim(framing.lookat_m, framing.distance_m, framing.azimuth_deg, framing.elevation_deg)
        self.executive.tracing = True  # the caption follows every statement
        self._font = ImageFont.load_default(size=CAPTION_PX)
        # written beside the target and renamed at the end: a run that dies leaves no half video over an old one
        self.path = Path(path)
        handle, temporary = tempfile.mkstemp(dir=self.path.resolve().parent, prefix=f".{self.path.name}.", suffix=".mp4")
        os.close(handle)
        self._temporary = Path(temporary)
        try:
            self._writer = imageio.get_writer(temporary, format="FFMPEG", mode="I", fps=fps, codec="libx264",
                                              pixelformat="yuv420p", macro_block_size=16, quality=7)
        except Exception as error:  # no ffmpeg, a folder that cannot be written
            self.camera.close()
            self._temporary.unlink(missing_ok=True)
            raise UsageError(f"--video {path}: cannot write a video there ({type(error).__name__}: {error})") from None
        self._write()  # the cell as it stands before anything moves

    def monitor(self, robot: Any) -> Any:
        """Film `robot`'s motion cycles from now on (it calls on_tick) until close(); the robot for the executive."""
        robot.tick_listeners.add(self.on_tick)
        self._listening = robot.tick_listeners
        return robot

    def on_tick(self) -> None:
        while self.robot.time_s() >= self.frames / self.fps - CLOCK_EPS_S:
            self._write()

    def _write(self) -> None:
        picture = Image.fromarray(self.camera.picture())
        draw = ImageDraw.Draw(picture)
        band = CAPTION_PX + 12
        draw.rectangle((0, picture.height - band, picture.width, picture.height), fill=(20, 20, 20))
        text = statement_caption(self.executive, self.frames / self.fps)
        draw.text((8, picture.height - band + 5), text, fill=(255, 255, 255), font=self._font)
        self._writer.append_data(np.asarray(picture))
        self.frames += 1

    def close(self) -> None:
        """Stop filming, finish the file, put it in its place and free the renderer."""
        self._listening.discard(self.on_tick)
        try:
            self._writer.close()
            os.chmod(self._temporary, _mode_for(self.path))
            os.replace(self._temporary, self.path)
        finally:
            self._temporary.unlink(missing_ok=True)
            self.camera.close()


def _mode_for(path: Path) -> int:
    """A replaced file keeps its mode; a new one gets the user's umask (mkstemp's own file is private)."""
    if path.exists():
        return path.stat().st_mode & 0o777
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask
