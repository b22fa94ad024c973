"""The state feedback's compiled schedule and step (numba) compute what the numpy code they were written from computes."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

from orc_rpl.motion import CartesianMotion, JointMotion, Params, make_virtual_motion_layer
from orc_rpl.plant import compiled
from orc_rpl.world.pose import Pose

pytestmark = [pytest.mark.sim, pytest.mark.skipif(not compiled.AVAILABLE, reason="the kernels are off (numba not installed, or ORC_RPL_NO_JIT=1)")]

#: What a schedule leaves that the steps use: the sampled model, the gains, the Riccati solutions carried on.
OUTPUTS = ("ad", "bd", "k", "l", "_p", "_s")
#: What the schedule compares to keep the gains (`INERTIA_TOLERANCE`, `GAINS_SETTLED`), and its flags and counts.
KEPT = ("link_inertia", "k", "l", "ad", "bd", "_flags")


@pytest.fixture(autouse=True)
def _kernels_back_on() -> Iterator[None]:
    before = compiled.use_kernels(True)
    yield
    compiled.use_kernels(before)


def _layer() -> Any:
    layer = make_virtual_motion_layer("irb2400", backend="servo", plant="realistic", seed=3, elastic=True,
                                      gear_feedforward=True, state_feedback=True)
    layer.backend.loop.set_payload(5.0, known=False)
    return layer


def _moves(layer: Any) -> None:
    """A joint move in a zone, one back with a declared load (the model's inertias change), a line."""
    home = np.array(layer.kin.arm.home_q)
    p = Pose.from_matrix(layer.fk(home))
    for motion, params in [(JointMotion(tuple(home + np.array([0.6, 0.3, -0.2, 0.4, -0.3, 0.8]))), Params(zone_m=0.05)),
                           (JointMotion(tuple(home)), Params(load_kg=4.0)),
                           (CartesianMotion(Pose(p.x, p.y + 0.2, p.z - 0.15, p.a, p.b, p.c)), Params())]:
        layer.wait(layer.move(motion, params))


def test_the_compiled_schedule_gives_the_numpy_schedules_model_and_gains_over_a_recorded_run() -> None:
    layer = _layer()
    layer.backend.loop.use_compiled_law(False)   # the Python loop, which calls the law's schedule (the kernel's runs it inside)
    law = layer.backend.loop.state_feedback
    schedule = law.schedule
    worst, compared = [0.0], [0]

    def both(q: np.ndarray, qd_ref: Any = None, iterations: Any = None) -> None:
        # the same cycle twice from the same state: numpy first (the reference), then the kernel, which goes on
        solved = law.solved
        saved = {name: np.array(getattr(law, name)) for name in ("_p", "_s", "moving", "state", "held_link_nm",
                                                                 "held_rotor_nm", *KEPT)}
        compiled.use_kernels(False)
        schedule(q, qd_ref, iterations)
        reference = [np.array(getattr(law, name)) for name in OUTPUTS]
        for name, value in saved.items():   # the law's arrays are written in place, never rebound
            getattr(law, name)[...] = value
        compiled.use_kernels(True)
        schedule(q, qd_ref, iterations)
        if not solved or iterations == 0:
            return   # solved anew: numpy's solver in both
        compared[0] += 1
        for name, want in zip(OUTPUTS, reference):
            got = getattr(law, name)
            assert got.shape == want.shape, name
            worst[0] = max(worst[0], float(np.max(np.abs(got - want)) / np.max(np.abs(want))))

    law.schedule = both
    _moves(layer)
    assert compared[0] > 500   # every motion cycle of the moves
    assert law.scheduled > 100   # of which these made the gains again (the others kept them, in both)
    assert worst[0] <= 1e-10, worst[0]


def test_the_compiled_step_gives_the_numpy_steps_references_torques_and_filter_over_a_recorded_run() -> None:
    layer = _layer()
    layer.backend.loop.use_compiled_law(False)   # the Python loop, which calls the law's step one call at a time
    law = layer.backend.loop.state_feedback
    worst, steps = [0.0], [0]

    def compare(got: Any, want: Any) -> None:
        got, want = np.asarray(got, dtype=float), np.asarray(want, dtype=float)
        assert got.shape == want.shape
        worst[0] = max(worst[0], float(np.max(np.abs(got - want)) / max(float(np.max(np.abs(want))), 1e-300)))

    def twice(method: Any, saved: tuple[str, ...], outputs: tuple[str, ...]) -> Any:
        """The step's method from the same state with numpy (the reference), then compiled (which goes on)."""
        def both(*args: Any) -> Any:
            before = {name: np.array(getattr(law, name)) for name in saved}
            compiled.use_kernels(False)
            want = method(*[np.array(a) for a in args])
            want_state = [np.array(getattr(law, name)) for name in outputs]
            for name, value in before.items():
                getattr(law, name)[...] = value
            compiled.use_kernels(True)
            got = method(*args)
            for name, value in zip(outputs, want_state):
                compare(getattr(law, name), value)
            if want is not None:
                for g, w in zip(got, want):
                    compare(g, w)
            steps[0] += 1
            return got
        return both

    law.references = twice(law.references, ("twist_rad", "_link_other"), ("twist_rad", "_link_other"))
    law.update = twice(law.update, ("state",), ("state",))
    law.applied = twice(law.applied, ("state",), ("state",))
    _moves(layer)
    assert steps[0] > 3 * 2000   # every 1 ms step of the moves, three calls each
    assert worst[0] <= 1e-10, worst[0]


def _final_links(law_kernels: bool) -> np.ndarray:
    layer = _layer()
    loop = layer.backend.loop
    if not law_kernels:
        loop.state_feedback._kernels = None   # the numpy law; the plant's kernels the same in both runs
    _moves(layer)
    return np.array(loop.cell.true_q)


def test_a_run_with_the_compiled_law_ends_where_the_numpy_laws_run_ends() -> None:
    # the last bits differ, and the encoder's rounding (a count is 2.5e-8 rad) can turn that into a count
    np.testing.assert_allclose(_final_links(True), _final_links(False), rtol=0.0, atol=1e-6)
