"""External axes in the arm's path coordinate: the arm and a turning positioner stay synchronised, the track moves
the robot, and the stages' combined range leaves a feasible motion exactly nominal."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from orc_rpl.arm.external import AxisLimits, ExternalAxisStage, StagedPathVelocityController, combine
from orc_rpl.errors import UsageError
from orc_rpl.motion import CartesianMotion, Params, make_virtual_motion_layer
from orc_rpl.motion.external import coordinated_motion, external_axes_of, shortest_time_s, world_frame_in_base
from orc_rpl.plant.world_scene import cell_from_world
from orc_rpl.world import load_world
from orc_rpl.world.pose import Pose

CELL = Path(__file__).parents[2] / "worlds" / "positioner_cell.yaml"


def _cell(plant: str = "realistic") -> tuple:
    world = load_world(CELL)
    layer = make_virtual_motion_layer(cell=cell_from_world(world), plant=plant, seed=1)
    layer.external = external_axes_of(world)
    tool = world.tool_pose("torch").matrix()
    start = world.relative_pose("plate.seam_start", "robot").matrix()
    h = layer.move(CartesianMotion(Pose.from_matrix(start), kind="joint", tool=tool))
    layer.wait(h)
    layer.run_for(0.2)
    return world, layer, tool


def test_the_tcp_follows_the_seam_on_the_turning_plate_within_half_a_millimetre() -> None:
    world, layer, tool = _cell()
    cell = layer.backend.loop.cell
    a = world.relative_pose("plate.seam_start", "plate").matrix()
    b = world.relative_pose("plate.seam_end", "plate").matrix()
    targets = {"turn": math.pi / 2, "track": 0.2}
    motion = coordinated_motion(world_frame_in_base(world, "plate"), a, b, {"turn": 0.0, "track": 0.0}, targets, tool)
    h = layer.external.request(layer, motion, Params(), targets)
    p0, p1 = a[:3, 3], b[:3, 3]
    worst = 0.0
    while not h.done:
        layer.tick()
        # measured in the simulated cell: the TCP relative to the plate's frame, both from the plant
        tcp = np.linalg.inv(cell.axes.body_pose("turn")) @ cell.flange_pose() @ tool
        p = tcp[:3, 3]
        u = float(np.clip(np.dot(p - p0, p1 - p0) / np.dot(p1 - p0, p1 - p0), 0.0, 1.0))
        worst = max(worst, float(np.linalg.norm(p - (p0 + u * (p1 - p0)))))
    layer.run_for(0.3)
    assert h.error is None
    assert worst < 0.5e-3
    values = cell.axes.values()
    assert values["turn"] == pytest.approx(math.pi / 2, abs=1e-3) and values["track"] == pytest.approx(0.2, abs=1e-4)
    # the move took at least what the turn's speed and acceleration limits need
    assert h.end_time_s - h.start_time_s >= shortest_time_s(math.pi / 2, layer.external.limits["turn"])


def test_the_track_carries_the_robot_to_the_station() -> None:
    world, layer, tool = _cell()
    cell = layer.backend.loop.cell
    moved = world.with_axes({"track": 0.35})
    station = moved.relative_pose("station", "robot")
    h = layer.external.request(layer, CartesianMotion(station, kind="joint", tool=tool), Params(), {"track": 0.35})
    layer.wait(h)
    layer.run_for(0.5)
    assert cell.axes.values()["track"] == pytest.approx(0.35, abs=1e-4)
    # where the TCP is in the cell (the scene's origin is the world's here) against the station's world pose
    tcp = cell.flange_pose() @ tool
    assert np.linalg.norm(tcp[:3, 3] - world.world_pose("station").matrix()[:3, 3]) < 1e-3


def test_an_axis_the_cell_does_not_have_is_a_usage_error() -> None:
    world, layer, tool = _cell("ideal")
    with pytest.raises(UsageError, match="no external axis 'tilt2'"):
        layer.external.request(layer, CartesianMotion(Pose(1, 0, 1), kind="joint"), Params(), {"tilt2": 0.1})


def _line(x: float, order: int) -> float:
    return (0.5 * x, 0.5, 0.0)[order]


def test_a_stage_limits_s_double_dot_by_its_acceleration_and_the_stages_combine() -> None:
    stage = ExternalAxisStage("turn", _line, AxisLimits(speed_si=1.0, acceleration_si=2.0))
    assert stage.admissible(0.3, 1.0) == pytest.approx((-4.0, 4.0))   # |0.5 s''| <= 2
    assert stage.reference(0.3, 1.0, 2.0) == pytest.approx((0.15, 0.5, 1.0))
    assert stage.admissible(0.3, 3.0)[1] == 0.0                       # above its speed limit: slow down only
    assert combine([(-4.0, 4.0), (-1.0, 9.0), (-math.inf, 3.0)]) == (-1.0, 3.0)


def test_with_stages_that_never_saturate_the_reference_equals_the_nominal_sample_for_sample() -> None:
    t = np.arange(0, 1001) * 0.001
    x_f = 0.5 * (1 - np.cos(np.pi * t))        # a smooth rest-to-rest profile over 1 s
    sd_f = 0.5 * np.pi * np.sin(np.pi * t)

    def path(x, order):  # a one-joint path q = x
        xs = np.atleast_1d(np.asarray(x, dtype=float))
        out = xs[:, None] if order == 0 else np.full((len(xs), 1), 1.0 if order == 1 else 0.0)
        return out if np.ndim(x) else out[0]

    loose = ExternalAxisStage("turn", _line, AxisLimits(speed_si=10.0, acceleration_si=100.0))
    pvc = StagedPathVelocityController(path, x_f, sd_f, 4, 0.001, None, np.array([1.0]), [loose])
    assert all(pvc.cycle(k) is None for k in range(1, 251)) and pvc.done and pvc.scaled_cycles == 0
    tight = ExternalAxisStage("turn", _line, AxisLimits(speed_si=10.0, acceleration_si=0.5))
    pvc = StagedPathVelocityController(path, x_f, sd_f, 4, 0.001, None, np.array([1.0]), [tight])
    rows = [pvc.cycle(k) for k in range(1, 400)]
    assert any(r is not None for r in rows) and pvc.lag_s() >= 0.0
