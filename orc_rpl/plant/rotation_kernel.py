"""The plant room's compiled rotation about a unit axis (Rodrigues' formula), inlined into the kernels that walk a chain
of joints: the compiled inverse dynamics (servo/rnea_kernel.py) and the compiled IK tracking (motion/ik_kernels.py)."""

from __future__ import annotations

import math

from orc_rpl.plant.compiled import inlined_kernel


@inlined_kernel
def axis_rotation(x: float, y: float, z: float, angle: float) -> tuple[float, ...]:  # pragma: no cover - compiled
    """The rotation by `angle` (rad) about the unit axis (x, y, z), row by row: (r00, r01, r02, r10, ..., r22)."""
    c, s = math.cos(angle), math.sin(angle)
    t = 1.0 - c
    return (c + x * x * t, x * y * t - z * s, x * z * t + y * s,
            y * x * t + z * s, c + y * y * t, y * z * t - x * s,
            z * x * t - y * s, z * y * t + x * s, c + z * z * t)
