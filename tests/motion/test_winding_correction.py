"""The winding-temperature estimate, corrected online from the drives' voltage and current, against the plant."""

from __future__ import annotations

import numpy as np
import pytest

from orc_rpl.motion import JointMotion, Params, make_virtual_motion_layer
from orc_rpl.robot.plants import plant_spec

pytestmark = pytest.mark.sim

MOVES_DEG = ((0, -30, -40, 0, 30, 0), (150, 70, -20, 0, -60, 90), (-100, -40, 10, 90, 40, 0))


def _duty(corrected: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(plant rise, estimated rise, measured R20) after two rounds of fast moves with 10 kg."""
    layer = make_virtual_motion_layer("irb2400", plant="realistic", seed=4)
    if not corrected:
        layer.winding.measurement = None
    loop = layer.backend.loop
    loop.cell.warm_up()
    loop.set_payload(10.0, known=False)
    for _ in range(2):
        for target in MOVES_DEG:
            layer.wait(layer.move(JointMotion(tuple(np.radians(target))), Params(load_kg=10.0)))
    return loop.cell.winding_rise_k, layer.winding.rise_k.copy(), layer.winding.r20_ohm


def test_the_drives_measure_the_windings_resistance_at_the_cold_start() -> None:
    _, _, r20 = _duty(True)
    spec = plant_spec("irb2400")
    plant_r20 = np.array(spec.winding_resistance_ohm) * spec.plant_resistance_factor
    assert np.all(np.isfinite(r20[:3])), "the three large motors carry current from the start"
    assert np.allclose(r20[:3], plant_r20[:3], rtol=0.003), "the plant's own resistance, not the data sheet's"


def test_the_correction_brings_the_estimate_closer_to_the_plants_windings() -> None:
    plant, corrected, _ = _duty(True)
    _, model_only, _ = _duty(False)
    error_corrected, error_model = np.abs(corrected - plant)[:3], np.abs(model_only - plant)[:3]
    assert np.max(error_corrected) < 0.5 * np.max(error_model), (error_corrected, error_model)
