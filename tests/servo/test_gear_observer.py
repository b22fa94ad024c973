"""The gear-torque observer: each elastic gear's torque seen from the motor side, and what the model lacks of it."""

from __future__ import annotations

import numpy as np
import pytest

from orc_rpl.errors import UsageError
from orc_rpl.motion import JointMotion, Params, make_virtual_motion_layer
from orc_rpl.servo.gear_observer import GearTorqueObserver


def test_the_observer_finds_the_gear_torque_from_the_rotors_speed_and_the_motors_torque() -> None:
    rotor, k, dt = np.array([4.0, 2.0]), np.array([1.5e5, 1.0e5]), 0.004
    gear = np.array([300.0, -80.0])   # what the gears carry: the rotor accelerates by the rest of the motor's torque
    observer = GearTorqueObserver(rotor, k, lambda q, qd, qdd: rotor * qdd)   # a model of the rotors alone
    observer.reset(np.zeros(2))
    qd = np.zeros(2)
    for i in range(100):
        tau = np.array([350.0, -50.0]) + 20.0 * np.sin(0.3 * i)
        qd = qd + (tau - gear) / rotor * dt
        observer.update(np.zeros(2), qd, tau, dt)
    assert np.allclose(observer.torque_nm, gear, atol=1e-6), "no double differentiation: the momentum balance"
    assert np.allclose(observer.twist_rad, gear / k)
    assert np.allclose(observer.excess_nm, gear, atol=1.0), "the model knows none of the link's torque here"


def test_the_observed_twist_is_nearer_the_links_than_the_commanded_one_under_an_undeclared_payload() -> None:
    layer = make_virtual_motion_layer("irb2400", plant="realistic", elastic=True, gear_feedforward=True,
                                      gear_observer=True)
    loop = layer.backend.loop
    loop.set_payload(15.0, known=False)   # the program declares 10 kg below
    observed, commanded = [], []

    def sample() -> None:
        true_twist = loop.cell.true_q - loop.cell.link_q
        if abs(loop.cell.true_qd[1]) > 0.2:   # moving: the static friction is out of the way
            observed.append(np.abs(loop.observer.twist_rad - true_twist)[:3])
            commanded.append(np.abs(loop.twist.twist_rad - true_twist)[:3])

    loop.on_step.append(sample)
    layer.wait(layer.move(JointMotion(tuple(np.radians((60, 40, -20, 0, 30, 0)))), Params(load_kg=10.0)))
    observed_p95, commanded_p95 = np.percentile(observed, 95, axis=0), np.percentile(commanded, 95, axis=0)
    # measured 0.10 0.07 0.06 against 0.36 0.29 0.51 mrad (j1..j3)
    assert np.all(observed_p95 < commanded_p95), (observed_p95, commanded_p95)
    assert observed_p95.max() < 1.5e-4


def test_the_observer_is_a_part_of_the_gears_feed_forward() -> None:
    with pytest.raises(UsageError, match="gear_observer is a part of the gears' feed-forward"):
        make_virtual_motion_layer("irb2400", plant="realistic", elastic=True, gear_observer=True)


def test_an_observer_on_its_own_reads_every_calls_mean_torque() -> None:
    layer = make_virtual_motion_layer("irb2400", plant="realistic", elastic=True)   # no feed-forward: no twist
    loop = layer.backend.loop
    k = np.array(loop.cell.plant.gear_stiffness_nm_rad)
    observer = GearTorqueObserver(loop.cell.motor_inertia_kg_m2, k, loop.servo.inverse_dynamics)
    observer.friction_of = loop.servo.friction_in_use   # the nominal friction: right for a warm plant
    loop.set_gear_observer(observer)
    loop.reset(np.array(layer.reference_q()))
    loop.cell.warm_up()
    errors = []

    def sample() -> None:
        if abs(loop.cell.true_qd[1]) > 0.2:
            errors.append(abs(observer.twist_rad[1] - (loop.cell.true_q - loop.cell.link_q)[1]))

    h = layer.move(JointMotion((0.3, -0.2, 0.1, 0.0, 0.3, 0.0)), Params())
    while not h.done:   # sampled once a motion cycle: no per-step callback, the drives' calls as in a plain run
        layer.tick()
        sample()
    # measured 0.12 mrad at the ends of the motion cycles (0.40 mrad step by step: the move is not averaged
    # here and the gears ring faster than the observer follows); an observer that missed the drives' torque
    # would be off by 3.7 mrad (the compiled kernel, which reports no mean torque, measured)
    assert len(errors) > 50 and np.percentile(errors, 95) < 3e-4
