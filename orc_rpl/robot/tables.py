"""The robot room's plant tables: the check every plant description makes of its per-joint values."""

from __future__ import annotations

import math
from typing import Any

from orc_rpl.errors import UsageError


def check_per_joint(spec: Any, names: tuple[str, ...]) -> None:
    """A plant description's per-joint tables: as many finite values >= 0 as it has Coulomb frictions (UsageError)."""
    n = len(spec.coulomb_nm)
    for name in names:
        values = getattr(spec, name)
        if len(values) != n or not all(math.isfinite(v) and v >= 0 for v in values):
            raise UsageError(f"plant of {spec.robot!r}: {name} must be {n} finite numbers >= 0, got {values!r}")
