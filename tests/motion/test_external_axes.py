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
from benchmarks import bench_external_axes
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
    # the benchmark's motion: the torch along the plate's seam while the table turns a quarter and the track runs,
    # the TCP measured relative to the plate in the simulated cell every motion cycle
    result = bench_external_axes.run("realistic", 1, lead=True)
    assert result["dev_mm"] < 0.5
    assert result["turn_error_mrad"] < 1.0 and result["track_error_mm"] < 0.1
    # the move took at least what the turn's speed and acceleration limits need
    limits = external_axes_of(load_world(CELL)).limits["turn"]
    assert result["duration_s"] >= shortest_time_s(math.pi / 2, limits)


@pytest.mark.sim
def test_the_tcp_follows_the_seam_within_half_a_millimetre_on_elastic_gears_too() -> None:
    # the same seam on the elastic gears under their state feedback: a cycle of the arm's references that brakes or
    # speeds up far off the nominal is a step of every gear's twist the links cannot follow (0.77 mm when the turn's
    # profile had spikes in its second derivative)
    assert bench_external_axes.run("elastic-gears", 1, lead=True)["dev_mm"] < 0.5


def test_a_stages_range_of_s_double_dot_moves_smoothly_along_the_path() -> None:
    # the turn's profile along the seam's joint path is interpolated as the arm's path is (a cubic spline through the
    # knots): its second derivative, and the stage's range of s'' with it, has no spike near a knot (a difference
    # quotient of the values, linear between the knots, moved the range by some 26 /s^2 there)
    world, layer, tool = _cell("ideal")
    a = world.relative_pose("plate.seam_start", "plate").matrix()
    b = world.relative_pose("plate.seam_end", "plate").matrix()
    targets = bench_external_axes.TARGETS
    motion = coordinated_motion(world_frame_in_base(world, "plate"), a, b, {"turn": 0.0, "track": 0.0}, targets, tool)
    layer.external.request(layer, motion, Params(), targets)
    traj = layer._traj
    turn = next(stage for stage in layer.external.stages(traj, layer._in_traj) if stage.name == "turn")
    ranges = np.array([turn.admissible(x, 1.3) for x in np.arange(0.0, traj.path.length, 2e-5)])
    assert np.abs(np.diff(ranges, axis=0)).max() < 0.1, "the turn's range of s'' jumps along the path (1/s^2)"
    # and the profile still goes through the values linear in the seam's coordinate at the knots
    _, s = traj.path.owner_and_s(traj.path.x_knots)
    assert [turn.profile(x, 0) for x in traj.path.x_knots] == pytest.approx(targets["turn"] * s, abs=1e-12)


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
    assert any(r is not None for r in rows) and pvc.scaled_cycles > 0
    slow = ExternalAxisStage("track", _line, AxisLimits(speed_si=10.0, acceleration_si=100.0, lag_s=0.02))
    pvc = StagedPathVelocityController(path, x_f, sd_f, 4, 0.001, None, np.array([1.0]), [loose, slow])
    assert pvc.lag_s() == 0.02  # the time lag through the stages: the largest of the arm's and each axis' own
