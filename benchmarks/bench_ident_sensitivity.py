"""Application benchmark: IDENTMOVE on the cold realistic arm when the controller's warm-up estimate is wrong.

Run: python benchmarks/bench_ident_sensitivity.py [--trials 1000] [--seed 1]

The controller's gearbox warm-up estimate (orc_rpl/motion/gear_friction.py) integrates the law and the class
figures the plant description gives (cold factor 2, warm rise 6 K, time constant 1200 s, the gearboxes' Rth).
A real gearbox does not follow its class figures exactly, so this benchmark runs bench_applications'
identification trials (the same recordings, envelope and seed) with the estimate's figures off by 25 %, both
ways, while the plant keeps its own: `low` has a quarter less cold excess and Rth, a fifth shorter time
constant and a quarter larger warm rise (the estimate predicts less warming), `high` the opposite. Printed per
variant: ident_correct_pct (among confident answers), ident_abstain_pct, ident_false_confident, and the cold
robot's largest tared error; the figures with the estimate's own figures are bench_applications' lines.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import bench_applications  # noqa: E402  (the trials live there)
from orc_rpl.motion import gear_friction  # noqa: E402

#: (scale of cold excess and Rth, scale of the time constant, scale of the warm rise) per variant
VARIANTS = {"low": (0.75, 0.8, 1.25), "high": (1.25, 1.2, 0.8)}
PRINTED = ("ident_correct_pct", "ident_abstain_pct", "ident_false_confident", "ident_cold_max_error_kg")


@contextmanager
def estimate_off_by(scales: tuple[float, float, float]) -> Iterator[None]:
    """Every GearFriction built inside is given class figures scaled as `scales` says; the plant is untouched."""
    excess_scale, time_scale, rise_scale = scales
    original = gear_friction.GearFriction.__init__

    def scaled(self: gear_friction.GearFriction, coulomb_nm: Sequence[float], viscous_nm_s: Sequence[float],
               gear_rth_k_w: Sequence[float], gear_time_constant_s: float, cold_friction_factor: float,
               warm_rise_k: float, *rest: object) -> None:
        original(self, coulomb_nm, viscous_nm_s, [rth * excess_scale for rth in gear_rth_k_w],
                 gear_time_constant_s * time_scale, 1.0 + (cold_friction_factor - 1.0) * excess_scale,
                 warm_rise_k * rise_scale, *rest)

    gear_friction.GearFriction.__init__ = scaled  # type: ignore[method-assign]
    try:
        yield
    finally:
        gear_friction.GearFriction.__init__ = original  # type: ignore[method-assign]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=1000)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    for name, scales in VARIANTS.items():
        with estimate_off_by(scales):
            figures = bench_applications.identification(args.trials, args.seed, "realistic")
        for key in PRINTED:
            print(f"estimate_{name}_{key}={figures[key]}", flush=True)


if __name__ == "__main__":
    main()
