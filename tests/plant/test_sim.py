"""Tests of the virtual cell: one model with the arm, determinism, IO numbering, payload, pictures."""

from __future__ import annotations

import os

import numpy as np
import pytest

from orc_rpl.robot import load_robot
from orc_rpl.errors import UsageError
from orc_rpl.plant import CellIO, default_cell
from orc_rpl.plant.sim import SimCell

pytestmark = pytest.mark.sim


@pytest.mark.parametrize("robot", ["irb2400", "ur5e"])
def test_cell_flange_is_where_the_arm_model_says(robot: str) -> None:
    cell, arm = SimCell(robot), load_robot(robot)
    q = arm.home_q + 0.3
    cell.reset(q)
    np.testing.assert_allclose(cell.flange_pose(), arm.fk(q), atol=1e-12)
    assert cell.timestep_s == 0.001
    np.testing.assert_array_equal(cell.tau_max, arm.tau_max)


def test_default_cell_has_the_table_in_front_below_the_workspace() -> None:
    top = next(b for b in default_cell().boxes if b.name == "table_top")
    assert top.center_m[2] + top.half_size_m[2] == pytest.approx(0.35)
    assert top.center_m[0] - top.half_size_m[0] == pytest.approx(0.7)
    assert top.center_m[0] + top.half_size_m[0] == pytest.approx(1.3)


def test_unknown_robot_is_a_usage_error() -> None:
    with pytest.raises(UsageError, match="known robots: irb2400, so101, ur5e"):
        SimCell("puma")


def _run(cell: SimCell, steps: int) -> np.ndarray:
    arm_gravity = load_robot(cell.robot).gravity
    cell.reset()
    out = np.empty((steps, cell.n_joints))
    for k in range(steps):
        tau = arm_gravity(cell.q) + 50.0 * np.sin(0.01 * k + np.arange(cell.n_joints))
        cell.step(tau)
        out[k] = cell.q
    return out


def test_same_torques_give_a_bit_identical_trajectory() -> None:
    first = _run(SimCell(), 500)
    second = _run(SimCell(), 500)
    assert np.array_equal(first, second)
    assert np.array_equal(first, _run(SimCell(), 500)[:500])


def test_gravity_torque_holds_the_arm_still() -> None:
    cell, arm = SimCell(), load_robot()
    for _ in range(1000):
        cell.step(arm.gravity(cell.q))
    assert cell.time_s == pytest.approx(1.0)
    np.testing.assert_allclose(cell.q, arm.home_q, atol=1e-9)


def test_plant_saturates_torque_at_the_motor_limit() -> None:
    cell = SimCell()
    cell.step(np.full(6, 1e6))
    np.testing.assert_array_equal(cell.tau, cell.tau_max)


def test_payload_makes_the_arm_sag_unless_compensated() -> None:
    cell, arm = SimCell(), load_robot()
    cell.set_payload(10.0)
    for _ in range(100):
        cell.step(arm.gravity(cell.q, payload_kg=10.0))
    np.testing.assert_allclose(cell.q, arm.home_q, atol=1e-9)
    cell.reset()
    for _ in range(100):
        cell.step(arm.gravity(cell.q))
    assert abs(cell.q[1] - arm.home_q[1]) > 1e-4, "reset keeps the payload; the bare-arm torque lets it sag"


def test_io_is_numbered_from_one_like_the_language() -> None:
    io = CellIO()
    io.dig_out[1] = True
    io.ana_out[8] = 2.5
    assert io.dig_out[1] is True and io.dig_out.values[0]
    assert io.ana_out[8] == 2.5
    with pytest.raises(UsageError, match=r"DigIn\[17\] does not exist: DigIn has channels 1..16"):
        io.dig_in[17]
    with pytest.raises(UsageError, match=r"DigOut\[0\]"):
        io.dig_out[0] = True
    with pytest.raises(UsageError, match="digital"):
        io.dig_out[2] = 0.5


def test_io_process_models_run_every_step() -> None:
    cell = SimCell()

    def gun(io: CellIO, time_s: float) -> None:
        io.dig_in[3] = io.dig_out[3] and time_s >= 0.005

    cell.io.add_process(gun)
    cell.io.dig_out[3] = True
    for _ in range(4):
        cell.step(np.zeros(6))
    assert cell.io.dig_in[3] is False
    cell.step(np.zeros(6))
    assert cell.io.dig_in[3] is True


def test_render_png_writes_a_picture(tmp_path) -> None:
    cell = SimCell()
    try:
        path = cell.render_png(tmp_path / "cell.png", 320, 240)
    except UsageError as exc:
        pytest.skip(f"no offscreen OpenGL here ({os.environ.get('MUJOCO_GL')}): {exc}")
    finally:
        cell.close()
    assert path.stat().st_size > 1000


def test_realtime_mode_keeps_pace_with_the_wall_clock() -> None:
    import time

    cell = SimCell(realtime=True)
    start = time.perf_counter()
    for _ in range(60):
        cell.step(np.zeros(6))
    assert time.perf_counter() - start >= 0.055


def test_a_turned_box_is_placed_with_the_pose_angle_convention() -> None:
    import math

    from orc_rpl.plant import Box, CellDescription
    from orc_rpl.world.pose import rotation_zyx

    angles = (math.radians(90), 0.0, math.radians(10))
    cell = SimCell(cell=CellDescription(boxes=(Box("fixture", (1.0, 0.1, 0.36), (0.15, 0.1, 0.01), angles_rad=angles),)))
    model, data = cell._model, cell._data
    geom = next(i for i in range(model.ngeom) if model.geom(i).name == "fixture")
    np.testing.assert_allclose(data.geom_xmat[geom].reshape(3, 3), rotation_zyx(*angles), atol=1e-12)
