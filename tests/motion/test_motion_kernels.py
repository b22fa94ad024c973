"""The motion room's compiled per-cycle kernels compute what the numpy (Python) code they were written from computes."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

from orc_rpl.motion import JointMotion, Params, make_virtual_motion_layer
from orc_rpl.motion.paths import DensePath
from orc_rpl.motion.trajectory import SplinePath
from orc_rpl.plant import compiled

pytestmark = [pytest.mark.sim, pytest.mark.skipif(not compiled.AVAILABLE, reason="the kernels are off (numba not installed, or ORC_RPL_NO_JIT=1)")]


@pytest.fixture(autouse=True)
def _kernels_back_on() -> Iterator[None]:
    before = compiled.use_kernels(True)
    yield
    compiled.use_kernels(before)


def test_the_compiled_winding_sample_calibrates_and_corrects_as_the_python_code_over_a_run() -> None:
    layer = make_virtual_motion_layer("irb2400", plant="realistic", seed=4)
    layer.backend.loop.set_payload(10.0, known=False)
    winding = layer.winding
    sample = winding._sample
    worst, compared, corrected = [0.0], [0], [0]

    def both(*measured: Any) -> None:
        # the same sample twice from the same state: Python first (the reference), then the kernel, which goes on
        saved = (winding.rise_k.copy(), winding._sums.copy(), winding._flags.copy(), winding._calibrating,
                 winding._samples)
        compiled.use_kernels(False)
        sample(*measured)
        reference = (winding.rise_k.copy(), winding._sums.copy(), winding._flags.copy(), winding._calibrating)
        winding.rise_k[:], winding._sums[:], winding._flags[:] = saved[0], saved[1], saved[2]
        winding._calibrating, winding._samples = saved[3], saved[4]
        compiled.use_kernels(True)
        sample(*measured)
        assert np.array_equal(winding._flags, reference[2]) and winding._calibrating == reference[3]
        for got, want in zip((winding.rise_k, winding._sums), reference[:2]):
            worst[0] = max(worst[0], float(np.max(np.abs(got - want) / np.maximum(np.abs(want), 1.0))))
        compared[0] += 1
        corrected[0] += not np.array_equal(saved[0], winding.rise_k)

    winding._sample = both  # type: ignore[method-assign]
    for target in ((0, -30, -40, 0, 30, 0), (150, 70, -20, 0, -60, 90), (-100, -40, 10, 90, 40, 0)):
        layer.wait(layer.move(JointMotion(tuple(np.radians(target))), Params(load_kg=10.0)))
    assert compared[0] > 100 and corrected[0] > 5, (compared, corrected)
    assert np.all(winding._flags[0, :3]), "the large motors calibrate during the run"
    assert worst[0] <= 1e-10, worst


@pytest.mark.parametrize("points", [2, 3, 40])
def test_the_compiled_spline_gives_scipys_values_and_derivatives_on_and_between_the_knots_and_beyond(points: int) -> None:
    rng = np.random.default_rng(points)
    q = np.cumsum(rng.normal(size=(points, 6)), axis=0)
    path = SplinePath(DensePath(q, q[:, :3], np.ones(points, dtype=int), np.linspace(0.0, 1.0, points)))
    x = np.concatenate([path.x_knots, rng.uniform(-0.3, path.length + 0.3, 300), [0.0, path.length]])
    compiled_orders = path.orders(x)
    for order, got in enumerate(compiled_orders):
        want = path.spline(x, order)
        assert got.shape == want.shape
        assert float(np.max(np.abs(got - want))) <= 1e-10 * max(1.0, float(np.max(np.abs(want))))
