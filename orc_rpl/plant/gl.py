"""OpenGL for MuJoCo only when a picture is asked for: a run needs none, a snapshot, a video or a view does.

MuJoCo chooses its GL backend from `MUJOCO_GL` when it is first imported, and loading EGL or OSMesa
fails on a machine without the system library. So `before_import()` (called by the plant's modules
right before `import mujoco`) sets `MUJOCO_GL=disable` unless the user chose a backend, and
`request_rendering()` picks a working backend only when a picture is wanted: before the import by
setting `MUJOCO_GL`, after it by loading the backend's GL context for MuJoCo's renderer.
"""

from __future__ import annotations

import ctypes.util
import importlib
import os
import sys
from typing import Any

from orc_rpl.errors import UsageError

#: Offscreen backends we try, in order, with the system library each loads and the Debian package that has it.
BACKENDS: tuple[tuple[str, str, str], ...] = (("egl", "EGL", "libegl1"), ("osmesa", "OSMesa", "libosmesa6"))

#: MUJOCO_GL values that mean "no OpenGL at all".
_DISABLED = ("disable", "disabled", "off", "false", "0")

_state = {"chosen_by_us": False, "backend": ""}


def before_import() -> None:
    """Call right before the first `import mujoco`: no GL backend is loaded unless one was requested or chosen."""
    if "mujoco" in sys.modules:
        return
    if "MUJOCO_GL" not in os.environ:
        os.environ["MUJOCO_GL"] = "disable"
        _state["chosen_by_us"] = True


def import_mujoco() -> Any:
    """The `mujoco` module, imported the one way: without a GL backend unless one was requested or chosen.

    The `MUJOCO_GL=disable` set for the import is taken out of the environment again, so that programs this
    process starts (an `orc run` of `orc verify`, a test's subprocess) choose for themselves.
    """
    before_import()
    try:
        import mujoco
    except Exception as error:  # a MUJOCO_GL backend that is not installed makes the import itself fail
        raise render_error(error) from None
    finally:
        if _state["chosen_by_us"] and os.environ.get("MUJOCO_GL") == "disable":
            del os.environ["MUJOCO_GL"]
    return mujoco


def _advice() -> str:
    packages = " or ".join(f"'{package}'" for _, _, package in BACKENDS)
    values = " or ".join(f"MUJOCO_GL={name}" for name, _, _ in BACKENDS)
    return (f"install an offscreen OpenGL library (Debian/Ubuntu: apt-get install {packages.replace(chr(39), '')}) "
            f"and try {values}")


def _available() -> list[str]:
    """The backends whose system library is installed, in our order of preference."""
    return [name for name, library, _ in BACKENDS if ctypes.util.find_library(library)]


def request_rendering() -> str:
    """Make offscreen rendering possible (a snapshot, a video, a view); the backend's name, or a UsageError.

    The pendant's `:snapshot` calls this before it renders. Without any working backend the error names the
    Debian packages to install and the MUJOCO_GL values to try.
    """
    if _state["backend"]:
        return _state["backend"]
    user_choice = os.environ.get("MUJOCO_GL", "").strip().lower()
    if not _state["chosen_by_us"] and user_choice and user_choice not in _DISABLED:
        _state["backend"] = user_choice  # the user's own choice, made before MuJoCo was imported
        return user_choice
    candidates = _available()
    if not candidates:
        raise UsageError(f"no offscreen OpenGL backend is available for rendering; {_advice()}")
    if "mujoco" not in sys.modules:
        os.environ["MUJOCO_GL"] = candidates[0]
        _state["chosen_by_us"], _state["backend"] = False, candidates[0]
        return candidates[0]
    if user_choice in _DISABLED and not _state["chosen_by_us"]:
        raise UsageError(f"rendering is disabled by MUJOCO_GL={user_choice}; unset it or {_advice()}")
    errors = []
    for name in candidates:  # MuJoCo is imported without GL: load one backend's context for its renderer now
        try:
            module = importlib.import_module(f"mujoco.{name}")
            classic = importlib.import_module("mujoco.rendering.classic.gl_context")
        except Exception as error:  # a library that is present but does not load
            errors.append(f"{name}: {type(error).__name__}: {error}")
            continue
        classic.GLContext = module.GLContext
        _state["backend"] = name
        return name
    raise UsageError(f"no offscreen OpenGL backend could be loaded ({'; '.join(errors)}); {_advice()}")


def render_error(error: Exception) -> UsageError:
    """A rendering failure as the user reads it: what failed, the packages to install and the MUJOCO_GL values to try."""
    backend = _state["backend"] or os.environ.get("MUJOCO_GL", "")
    return UsageError(f"cannot render the cell offscreen with MUJOCO_GL={backend!r} "
                      f"({type(error).__name__}: {error}); {_advice()}")
