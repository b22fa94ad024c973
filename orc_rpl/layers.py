"""The layer order of the packages, written once: the architecture test and docs/architecture.md follow it.

A module may import modules of its own package and of packages in a lower tier, never of the
same tier or a higher one. Feedback travels up as signals and return values, never as imports.
"""

from __future__ import annotations

#: Tiers from the top (the `orc` command) to the bottom (shared value types); packages in one tier
#: do not import each other.
TIERS: tuple[tuple[str, ...], ...] = (
    ("__main__",),
    ("cli",),
    ("commands",),
    ("pendant", "view", "lsp", "verify"),
    ("transform",),
    ("executive", "checking"),
    ("application",),
    ("motion",),
    ("arm",),
    ("servo",),
    ("hardware",),
    ("plant",),
    ("robot",),
    ("world", "signals"),
    ("syntax",),
    ("errors", "atomic", "layers", "listeners"),
)

#: Heavy libraries and the one package allowed to import each (it wraps the library for the rest).
HEAVY_LIBRARIES: dict[str, str] = {
    "pinocchio": "robot",
    "toppra": "motion",
    "ruckig": "motion",
    "mujoco": "plant",
    # the compiler of the per-cycle kernels (plant/compiled.py); llvmlite is its code generator
    "numba": "plant",
    "llvmlite": "plant",
    "viser": "view",
    "imageio": "view",
    "imageio_ffmpeg": "view",
    "pygls": "lsp",
    "lsprotocol": "lsp",
    "dask": "verify",
    "distributed": "verify",
    "scservo_sdk": "hardware",
    "dynamixel_sdk": "hardware",
}


def tier_of(package: str) -> int:
    """The tier index of a top-level package of orc_rpl (0 is the top); KeyError for an unknown one."""
    for index, names in enumerate(TIERS):
        if package in names:
            return index
    raise KeyError(package)


def may_import(importer: str, imported: str) -> bool:
    """True when package `importer` may import package `imported` (its own, or one in a lower tier)."""
    return importer == imported or tier_of(imported) > tier_of(importer)
