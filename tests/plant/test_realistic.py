"""The realistic plant: friction that warms up, hot windings, encoders, masses the model does not know, seeded."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from orc_rpl.plant.realistic import THERMAL_EVERY_STEPS, RealisticCell
from orc_rpl.plant.sim import SimCell
from orc_rpl.robot import load_robot
from orc_rpl.robot.plants import PLANTS, plant_spec
from orc_rpl.errors import UsageError

pytestmark = pytest.mark.sim


def _hold_gravity(cell: SimCell, steps: int) -> np.ndarray:
    """Apply the model's gravity torque at home plus a sine on j1; return the measured speeds."""
    arm = load_robot(cell.robot)
    tau = arm.gravity(arm.home_q)
    out = []
    for k in range(steps):
        cell.step(tau + np.array([80.0 * np.sin(k * 0.01), 0, 0, 0, 0, 0]))
        out.append(cell.qd)
    return np.array(out)


def test_same_seed_same_run_other_seed_other_noise() -> None:
    a, b, c = (_hold_gravity(RealisticCell("irb2400", seed=s), 300) for s in (7, 7, 8))
    assert np.array_equal(a, b)
    assert not np.array_equal(a, c)


def test_the_servo_reads_quantised_angles_and_noisy_speeds() -> None:
    cell = RealisticCell("irb2400", seed=1)
    _hold_gravity(cell, 200)
    resolution = 2 * np.pi / plant_spec("irb2400").encoder_counts_per_rev
    counts = cell.q / resolution
    assert np.allclose(counts, np.round(counts), atol=1e-6)
    assert np.all(np.abs(cell.q - cell.true_q) <= resolution / 2 + 1e-15)
    noise = cell.qd - cell.true_qd
    assert 0.0 < np.max(np.abs(noise)) < 6 * plant_spec("irb2400").velocity_noise_rad_s


def test_cold_friction_is_twice_the_warm_and_falls_as_the_gearbox_warms() -> None:
    cell = RealisticCell("irb2400")
    spec = plant_spec("irb2400")
    coulomb, viscous = cell.friction_nm()
    assert np.allclose(coulomb, 2.0 * spec.plant_coulomb_factor * np.array(spec.coulomb_nm))
    assert np.allclose(viscous, 2.0 * spec.plant_viscous_factor * np.array(spec.viscous_nm_s))
    _hold_gravity(cell, 2000)
    assert cell.gear_rise_k[0] > 0.0 and cell.friction_factor[0] < 2.0, "j1 turns: its gearbox warms"
    cell.warm_up()
    assert np.all(cell.friction_factor < 1.01)
    warm_coulomb, _ = cell.friction_nm()
    assert np.allclose(warm_coulomb, spec.plant_coulomb_factor * np.array(spec.coulomb_nm), rtol=0.01)
    # MuJoCo applies what the description says
    assert np.allclose(cell._model.dof_frictionloss[:6], warm_coulomb)


def test_a_held_torque_heats_the_winding_with_its_time_constant() -> None:
    cell = RealisticCell("irb2400")
    spec = plant_spec("irb2400")
    _hold_gravity(cell, 4000)
    # j2 carries the arm: copper loss R i^2, first order towards Rth * P
    tau2 = float(np.mean(np.abs(cell.tau[1])))
    power = spec.winding_resistance_ohm[1] * spec.plant_resistance_factor * (tau2 / spec.torque_per_amp_nm_a[1]) ** 2
    time_constant = spec.winding_time_constant_s[1] * spec.plant_winding_time_factor
    expected = spec.winding_rth_k_w[1] * spec.plant_winding_rth_factor * power * (1 - np.exp(-4.0 / time_constant))
    assert cell.winding_rise_k[1] == pytest.approx(expected, rel=0.05)
    assert cell.winding_temperature_c[1] == pytest.approx(spec.ambient_c + cell.winding_rise_k[1])
    assert THERMAL_EVERY_STEPS * cell.timestep_s <= 0.05


def test_masses_differ_from_the_model_by_the_documented_few_percent() -> None:
    import mujoco

    arm = load_robot("irb2400")
    q = np.array([0.0, 0.6, 0.2, 0.0, 0.5, 0.0])
    model_g = arm.gravity(q)
    for cell, lo, hi in ((SimCell("irb2400"), 0.0, 1e-6), (RealisticCell("irb2400"), 0.01, 0.12)):
        cell.reset(q)
        cell.set_payload(0.0)
        cell._model.dof_frictionloss[:] = 0.0
        data = cell._data
        data.qvel[:] = 0.0
        data.qacc[:] = 0.0
        mujoco.mj_inverse(cell._model, data)
        plant_g = data.qfrc_inverse[:6]
        error = abs(plant_g[1] - model_g[1]) / abs(model_g[1])
        assert lo <= error <= hi, (type(cell).__name__, error)


def test_every_robot_with_a_plant_builds_and_an_unknown_one_is_a_clear_error() -> None:
    for name in PLANTS:
        assert RealisticCell(name).n_joints == plant_spec(name).n_joints
    with pytest.raises(UsageError, match="no realistic plant"):
        plant_spec("puma")


def _elastic_irb2400_at_home() -> tuple[Any, RealisticCell, Any, Any]:
    """The IRB 2400 on elastic gears under the servo (rigid gains, nominal friction), reset at home."""
    from orc_rpl.servo.loop import ServoLoop

    spec = plant_spec("irb2400")
    cell = RealisticCell("irb2400", elastic=True)
    loop = ServoLoop(load_robot("irb2400"), cell)
    loop.servo.set_friction(spec.coulomb_nm, spec.viscous_nm_s)
    arm = load_robot("irb2400")
    loop.reset(arm.home_q)
    return spec, cell, loop, arm


def test_elastic_gears_twist_under_load_and_the_servo_stays_stable() -> None:
    spec, cell, loop, arm = _elastic_irb2400_at_home()
    loop.hold(arm.home_q, 1500)
    twist = cell.link_q - cell.true_q
    # at rest the gear carries the motor's torque against the arm's weight: k * twist = -tau (j2 carries the arm)
    assert twist[1] == pytest.approx(-cell.tau[1] / spec.gear_stiffness_nm_rad[1], rel=0.05)
    assert np.max(np.abs(loop.servo.position_error)) < 1e-4, "the motor side is held"
    with pytest.raises(UsageError, match="no gear stiffness"):
        RealisticCell("ur5e", elastic=True)


def test_elastic_gears_start_wound_up_under_the_links_weight() -> None:
    spec, cell, loop, arm = _elastic_irb2400_at_home()
    wound = cell.link_q - cell.true_q
    assert abs(wound[1]) > 1e-4, "j2's gear carries the arm from the start"
    loop.hold(arm.home_q, 300)
    # held, the links stay where the wound gears put them: no drop, no ringing
    assert np.max(np.abs(cell.link_q - cell.true_q - wound)) < 0.05 * abs(wound[1])


@pytest.mark.parametrize("elastic", [False, True], ids=["rigid-gears", "elastic-gears"])
def test_the_joints_friction_steps_by_pgs_with_newtons_motion(elastic: bool) -> None:
    import mujoco

    pgs, newton = RealisticCell("irb2400", elastic=elastic), RealisticCell("irb2400", elastic=elastic)
    assert pgs._model.opt.solver == mujoco.mjtSolver.mjSOL_PGS, "friction is the only constraint: PGS is enough"
    newton._model.opt.solver = mujoco.mjtSolver.mjSOL_NEWTON   # MuJoCo's default, with its islands
    newton._model.opt.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_ISLAND)
    # cold friction (twice the warm) against a sine on j1 that reverses it and lets it stick at each reversal
    _hold_gravity(pgs, 1500)
    _hold_gravity(newton, 1500)
    assert np.max(np.abs(pgs.true_q - newton.true_q)) < 1e-6, "the same forces from either solver (rad)"
    assert np.max(np.abs(pgs.true_qd)) > 0.0


def test_a_cell_with_contacts_keeps_newton_for_them() -> None:
    import mujoco

    from orc_rpl.plant.world_scene import cell_from_world
    from orc_rpl.world import load_world

    world = load_world(Path(__file__).resolve().parents[2] / "worlds" / "deburring.yaml")
    cell = RealisticCell(cell=cell_from_world(world))
    assert cell._model.opt.solver == mujoco.mjtSolver.mjSOL_NEWTON
    assert not cell._model.opt.disableflags & int(mujoco.mjtDisableBit.mjDSBL_ISLAND)
