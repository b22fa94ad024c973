"""The servo tuned for elastic gears: bandwidths below each joint's anti-resonance, and a stable move on the two-mass plant."""

from __future__ import annotations

import numpy as np
import pytest

from orc_rpl.errors import UsageError
from orc_rpl.motion import JointMotion, MoveStatus, Params, make_virtual_motion_layer
from orc_rpl.plant.realistic import RealisticCell
from orc_rpl.robot import load_robot
from orc_rpl.robot.plants import plant_spec
from orc_rpl.servo.control import ServoGains
from orc_rpl.servo.two_mass import POSITION_OVER_VELOCITY, link_inertia_max, two_mass_gains


def test_bandwidths_sit_at_the_anti_resonance_where_it_is_below_the_default() -> None:
    arm, spec = load_robot("irb2400"), plant_spec("irb2400")
    rotor = RealisticCell("irb2400", elastic=True).motor_inertia_kg_m2
    gains = two_mass_gains(arm, rotor, spec.gear_stiffness_nm_rad)
    kp, bw = gains.per_joint(6)
    anti = np.sqrt(np.array(spec.gear_stiffness_nm_rad) / link_inertia_max(arm, rotor))
    low = anti < ServoGains().velocity_bw_rad_s
    assert low[:3].all() and not low[3:].any(), "j1..j3 of the IRB 2400 have slow gears"
    assert np.allclose(bw[low], anti[low]) and np.all(bw[~low] == 160.0)
    assert np.allclose(kp[low], np.minimum(POSITION_OVER_VELOCITY * bw[low], 40.0)) and np.all(kp[~low] == 40.0)
    # the rotor's loop over one 1 ms step stays below the explicit integration's limit of 2
    kv_h_over_rotor = (link_inertia_max(arm, rotor) + rotor) * bw * 1e-3 / rotor
    assert np.all(kv_h_over_rotor < 1.5)
    with pytest.raises(UsageError, match="per-joint servo gains are for 2 joints"):
        ServoGains(joint_velocity_bw_rad_s=(1.0, 2.0)).per_joint(6)


def _fast_move(elastic: bool) -> tuple[MoveStatus, float, np.ndarray]:
    layer = make_virtual_motion_layer("irb2400", plant="realistic", elastic=elastic)
    loop = layer.backend.loop
    loop.cell.warm_up()
    saturated = np.zeros(6)
    loop.on_step.append(lambda: np.add(saturated, loop.servo.saturated, out=saturated))
    h = layer.move(JointMotion((0.6, -0.3, 0.2, 0.0, 0.4, 0.0)), Params())
    layer.wait(h)
    return h.status, float(np.max(np.abs(loop.servo.position_error))), saturated


def test_a_fast_move_on_elastic_gears_ends_on_target_without_saturating() -> None:
    status, error, saturated = _fast_move(True)
    assert status is MoveStatus.READY
    assert error < 1e-3
    assert saturated.sum() == 0


def test_the_rigid_tuning_rings_against_elastic_gears() -> None:
    layer = make_virtual_motion_layer("irb2400", plant="realistic", elastic=True)
    loop = layer.backend.loop
    loop.servo.set_tuning(None)
    rigid = ServoGains()
    loop.servo._kp, loop.servo._velocity_bw = np.full(6, rigid.position_gain_1_s), np.full(6, rigid.velocity_bw_rad_s)
    saturated = np.zeros(6)
    loop.on_step.append(lambda: np.add(saturated, loop.servo.saturated, out=saturated))
    layer.wait(layer.move(JointMotion((0.6, -0.3, 0.2, 0.0, 0.4, 0.0)), Params()))
    assert saturated[:2].sum() > 0, "j1 and j2 saturate: their rotors ring against the gears"


def test_elastic_gears_belong_to_the_realistic_plant() -> None:
    with pytest.raises(UsageError, match="elastic gears are part of the realistic plant"):
        make_virtual_motion_layer("irb2400", plant="ideal", elastic=True)
