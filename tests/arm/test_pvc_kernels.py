"""The path velocity controller's compiled time-scaled cycle gives its Python reference's references, cycle by cycle."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

from orc_rpl.arm.pvc import PathVelocityController
from orc_rpl.motion import JointMotion, Params, make_virtual_motion_layer
from orc_rpl.plant import compiled

from .test_pvc import H, SUB, line, trapezoid

pytestmark = pytest.mark.skipif(not compiled.AVAILABLE, reason="no kernels to compare: numba is not installed or ORC_RPL_NO_JIT=1")


@pytest.fixture(autouse=True)
def _setting_kept() -> Iterator[None]:
    setting = compiled.ON
    yield
    compiled.use_kernels(setting)


def _checked(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """Every time-scaled cycle run twice from the same state, Python first (the reference), then compiled; the
    references, the state after and the count of changed cycles must be the same bits. Returns [cycles compared]."""
    compared = [0]
    scaled = PathVelocityController._scaled

    def both(self: PathVelocityController, row: int, nominal_ended: bool) -> Any:
        state = (self.x, self.sd, self.in_sync, self.done, self.scaled_cycles)
        compiled.use_kernels(False)
        reference = scaled(self, row, nominal_ended)
        after = (self.x, self.sd, self.in_sync, self.done, self.scaled_cycles)
        self.x, self.sd, self.in_sync, self.done, self.scaled_cycles = state
        compiled.use_kernels(True)
        got = scaled(self, row, nominal_ended)
        assert (self.x, self.sd, self.in_sync, self.done, self.scaled_cycles) == after
        for a, b in zip(got, reference):
            assert np.array_equal(a, b)
        compared[0] += 1
        return got

    monkeypatch.setattr(PathVelocityController, "_scaled", both)
    return compared


def test_a_torque_limited_line_late_and_braking_at_its_end(monkeypatch: pytest.MonkeyPatch) -> None:
    compared = _checked(monkeypatch)
    x, sd = trapezoid(4.0, 1.0)

    def against_a_load(q: np.ndarray, d1: np.ndarray, d2: np.ndarray, sd: float) -> tuple[np.ndarray, np.ndarray]:
        return 2.0 * d1, np.full(2, 3.0)

    for dynamics, limit in ((lambda q, d1, d2, s: (2.0 * d1, np.zeros(2)), 5.0), (against_a_load, 9.0 / 0.95)):
        controller = PathVelocityController(line, x, sd, SUB, H, dynamics, np.array([limit, limit]))
        k = 0
        while not controller.done and k < 10_000:
            k += 1
            controller.cycle(k)
        assert controller.done
    assert compared[0] > 100


@pytest.mark.sim
def test_an_undeclared_payload_on_the_cold_realistic_plant(monkeypatch: pytest.MonkeyPatch) -> None:
    compared = _checked(monkeypatch)
    compiled.use_kernels(True)
    layer = make_virtual_motion_layer(plant="realistic", seed=2)
    layer.backend.loop.set_payload(15.0, known=False)
    for target in ((0, -30, -40, 0, 30, 0), (60, 10, -20, 30, -40, 90)):
        h = layer.move(JointMotion(tuple(np.radians(target))), Params(load_kg=10.0, path_velocity=True))
        layer.wait(h)
    assert compared[0] > 20
