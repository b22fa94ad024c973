"""The one place a video asks for an OpenGL backend: decided before MuJoCo is first imported."""

from __future__ import annotations

import os
import sys


def request_rendering() -> None:
    """Ask for offscreen rendering: MuJoCo reads MUJOCO_GL when it is first imported, so call this before the
    plant is built. The user's own MUJOCO_GL (egl, osmesa) wins; headless EGL otherwise."""
    if "mujoco" not in sys.modules:
        os.environ.setdefault("MUJOCO_GL", "egl")
