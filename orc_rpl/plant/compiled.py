"""The plant room's compiler: numba for the per-step bookkeeping around mj_step, and mj_step callable from it.

The per-cycle work of the drives is a few dozen operations on six numbers; in numpy each costs a
call (0.2-0.7 us), compiled they cost nanoseconds. `kernel` compiles a function with numba
(`@njit(cache=True)`: the machine code is kept between runs, next to the source or, when the
installation is read-only, in numba's user cache folder; NUMBA_CACHE_DIR moves it);
`mj_step_intrinsic()` calls MuJoCo's `mj_step` from such a function (the addresses are
`MjModel._address` and `MjData._address`). Without numba (or without MuJoCo's shared library where
it is looked for), or with ORC_RPL_NO_JIT=1, `AVAILABLE` is False and the callers keep their numpy
code, which stays the reference the kernels are tested against.

numba is imported when the first module of kernels is (the objects that use kernels import their
module when they are made: a simulation's), never by `import orc_rpl...`: commands that simulate
nothing do not pay its import.
"""

from __future__ import annotations

import ctypes
import glob
import importlib
import importlib.util
import os
from collections.abc import Callable
from types import ModuleType
from typing import Any

from orc_rpl.plant.gl import import_mujoco

#: MuJoCo's mj_step under a name of our own in the JIT's symbol table (no clash with anyone's "mj_step").
STEP_SYMBOL = "orc_rpl_mj_step"

#: Set to 1 to run the numpy reference code instead of the compiled kernels (measurements, debugging).
DISABLE_ENV = "ORC_RPL_NO_JIT"


def _mujoco_library() -> ctypes.CDLL | None:
    """MuJoCo's shared library as the Python bindings load it (the same copy: the process has it already)."""
    folder = os.path.dirname(import_mujoco().__file__)
    for pattern in ("libmujoco.so*", "libmujoco*.dylib", "mujoco.dll"):
        for path in sorted(glob.glob(os.path.join(folder, pattern))):
            try:
                return ctypes.CDLL(path)
            except OSError:
                continue
    return None


def _load() -> tuple[Any, Any]:
    """(numba.njit, the mj_step intrinsic), or (None, None) when numba or MuJoCo's library is missing."""
    if not AVAILABLE:
        return None, None
    try:
        import llvmlite.binding as llvm
        import numba
        from llvmlite import ir
        from numba.core import cgutils
        from numba.extending import intrinsic
    except ImportError:
        return None, None
    library = _mujoco_library()
    if library is None:
        return None, None
    # The compiled code (and the cached code of an earlier run) calls the symbol; it is bound here, every run
    llvm.add_symbol(STEP_SYMBOL, ctypes.cast(library.mj_step, ctypes.c_void_p).value)

    @intrinsic
    def mj_step_at(typingctx: Any, model_address: Any, data_address: Any) -> Any:
        """mj_step(model, data) from compiled code; the arguments are the structs' addresses (integers)."""
        signature = numba.types.void(numba.types.intp, numba.types.intp)

        def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
            pointer = ir.IntType(8).as_pointer()
            function = cgutils.get_or_insert_function(builder.module, ir.FunctionType(ir.VoidType(), [pointer, pointer]),
                                                      STEP_SYMBOL)
            builder.call(function, [builder.inttoptr(args[0], pointer), builder.inttoptr(args[1], pointer)])
            return context.get_dummy_value()

        return signature, codegen

    return numba.njit, mj_step_at


#: True when the kernels can be compiled (numba is installed, ORC_RPL_NO_JIT is not set; False too once
#: numba or MuJoCo's library failed to load).
AVAILABLE = os.environ.get(DISABLE_ENV, "") in ("", "0") and importlib.util.find_spec("numba") is not None

#: The hot paths use the kernels now (read it as `compiled.ON` at each call; `use_kernels` sets it).
ON = AVAILABLE

_loaded: list[tuple[Any, Any]] = []


def _compiler() -> tuple[Any, Any]:
    """(numba.njit, the mj_step intrinsic), loaded once; (None, None) where the kernels are not AVAILABLE."""
    global AVAILABLE, ON
    if not _loaded:
        _loaded.append(_load())
        if _loaded[0][0] is None:
            AVAILABLE = ON = False
    return _loaded[0]


def use_kernels(on: bool) -> bool:
    """Run the compiled kernels (True, where AVAILABLE) or the numpy reference code (False) from now on,
    in the whole process; returns the previous setting (benchmarks and tests compare the two)."""
    global ON
    before, ON = ON, bool(on) and AVAILABLE
    return before


def kernels(module: str) -> ModuleType | None:
    """The module of kernels named `module` (its caller's own, e.g. "orc_rpl.servo.drive_kernels"),
    imported now, or None where the kernels are not AVAILABLE. The objects that run kernels call it when
    they are made (a simulation's), so that numba's import is paid only where something simulates; the
    name comes from the caller, so this room knows nothing of the rooms above it."""
    if not AVAILABLE:
        return None
    return importlib.import_module(module)


def kernel(function: Callable[..., Any]) -> Callable[..., Any]:
    """`function` compiled (numba, cached between runs); unchanged where numba is not AVAILABLE (then the
    caller must not call it in its hot path: it is the numpy code's job there)."""
    return _compiled(function, inline="never")


def inlined_kernel(function: Callable[..., Any]) -> Callable[..., Any]:
    """`kernel`, whose body numba also puts into the kernels that call it (a call between kernels otherwise
    costs some 35 ns: a status check and a return through memory; for the small kernels that others share)."""
    return _compiled(function, inline="always")


def _compiled(function: Callable[..., Any], inline: str) -> Callable[..., Any]:
    """`function` compiled with numba's `inline` option ("never" is numba's default), or unchanged without numba."""
    njit, _ = _compiler()
    if njit is None:
        return function
    return njit(cache=True, inline=inline)(function)  # type: ignore[no-any-return]


def mj_step_intrinsic() -> Any:
    """mj_step(model_address, data_address) for compiled code (None where the kernels are not AVAILABLE)."""
    return _compiler()[1]
