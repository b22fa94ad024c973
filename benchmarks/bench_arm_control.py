"""Arm-control benchmark: the path velocity controller on the realistic plant, and the winding-temperature estimate.

Run: python benchmarks/bench_arm_control.py [--robot irb2400] [--seed 0] [--elastic]
Fast joint motions at full speed, declared LOAD = 10 kg while the plant carries 15 kg,
from a cold start (twice the warm friction). The last lines are `key=value` figures (targets:
pvc_path_error_mm <= 0.5, saturated_cycle_fraction <= 0.01, nominal_equals_actual_when_feasible=True,
thermal_estimate_error_pct <= 5); no_pvc_path_error_mm is the same motions without the controller,
thermal_estimate_error_pct_model_only the thermal model without the correction from the drives' voltage and current.
Path errors count every servo step from the start of a move to the end of its FINE settling;
pvc_path_error_while_moving_mm only the steps while the reference moves.
--elastic: the same on the plant with elastic gears and the servo for them with the gears' feed-forward
(make_virtual_motion_layer(elastic=True, gear_feedforward=True), servo/two_mass.py);
the path errors are then the TCP's from the links' own angles (pvc_path_error_mm: where the tool
really is) and, pvc_encoder_path_error_mm, from the encoders through the controller's kinematics less
the twist its gear model commands. --without FEATURE (repeatable) switches off one of the elastic
gears' features to credit each: twist (the rotors' lead by the gears' twist), smoothing (trajectories
averaged over the anti-resonance periods), gain (the position loops at 0.25 of the velocity loops'
bandwidth instead of 0.8), friction (the servo's friction feed-forward the nominal warm one, not the
controller's gearbox estimate's), integral (the twist from the model's torque alone: neither the
servo's averaged integral nor, with --observer, the observer's excess). --observer: the torque the
model lacks in the twist from the gear-torque observer (servo/gear_observer.py) instead of the
servo's averaged integral (opt-in: make_virtual_motion_layer(..., gear_observer=True)). --state-feedback:
the slow joints under the two-mass state feedback (servo/state_feedback.py, opt-in:
make_virtual_motion_layer(..., state_feedback=True)). --load-at-rest: the carried load is on the plant
from the reset (the gears wound under it) and the drives hold the arm REST_S before the first move, as
after a brake release (the default hangs it on at time 0, as the first move starts; the load-at-rest run
is measured from its first move, the hold not counted). links_swing_after_{short,zone,stop}_moves_mrad: ringing
or hunting at rest after moves that are not averaged (two short moves; zone blends; a stop from full speed), and
links_swing_after_fine_moves_mrad after moves that are (two FINE moves from rest), the largest swing of j1..j3 (the
links' own angles on elastic gears) from where they settle, from 0.1 s after the end. --smoothing-share SHARE: with
--elastic, moves from rest averaged over this share of the anti-resonance periods (two_mass.smoothing_windows_s)
instead of whole periods; --scaled-averaging: with --state-feedback, every move from rest averaged over the share
of the whole windows its steps' twist of the gears calls for (motion/gear_steps.py, opt-in). A warm plant (warm_up) is a robot known to have run a while: the
controller's gearbox estimate is told so too (GearFriction.warm_up).
"""

from __future__ import annotations

import argparse

import numpy as np

from orc_rpl.motion import JointMotion, MotionLayer, Params, make_virtual_motion_layer
from orc_rpl.servo import state_feedback, two_mass

DECLARED_KG, CARRIED_KG = 10.0, 15.0
ELASTIC = [False]   #: the plant's elastic gears (--elastic)
WITHOUT: set[str] = set()   #: elastic gears' features switched off (--without)
FEATURES = ("twist", "smoothing", "gain", "friction", "integral")
OBSERVER = [False]   #: the gears' torque observer for the twist's extra torque (--observer)
STATE_FEEDBACK = [False]   #: the two-mass joints' state feedback instead of the cascade (--state-feedback)
SMOOTHING_SHARE: list[float | None] = [None]   #: the averaging windows' share of the periods (--smoothing-share)
SCALED_AVERAGING = [False]   #: moves from rest averaged over the share of the windows their steps call for (--scaled-averaging)
LOAD_AT_REST = [False]   #: the carried load hung on before the reset, the drives holding it first (--load-at-rest)
REST_S = 1.0   #: --load-at-rest: how long the drives hold the arm under its load before the first move (s)

#: The fast motions: joint moves (MOVE) at full speed, FINE, between these configurations (deg),
#: the first from home; the arm swings stretched out, where gravity and inertia use most of the torque.
TARGETS_DEG = ((0, -30, -40, 0, 30, 0), (150, 70, -20, 0, -60, 90), (-100, -40, 10, 90, 40, 0),
               (60, 80, -50, -90, 0, 0), (-60, 0, -50, 0, 90, 0))
PATH_SAMPLES = 4000   #: points of the programmed TCP path the deviation is measured against


def _programmed_tcp(layer: MotionLayer) -> tuple[np.ndarray, np.ndarray]:
    """The running trajectory's path as TCP segments (starts, directions), through the controller's kinematics."""
    path = layer._traj.path  # type: ignore[union-attr]
    x = np.linspace(0.0, path.length, PATH_SAMPLES)
    tcp = layer.kin.tcp_positions(path(x), None)
    return tcp[:-1], np.diff(tcp, axis=0)


def _distance(p: np.ndarray, starts: np.ndarray, directions: np.ndarray) -> float:
    rel = p - starts
    u = np.clip(np.einsum("ij,ij->i", rel, directions) / np.maximum(np.einsum("ij,ij->i", directions, directions), 1e-18), 0.0, 1.0)
    return float(np.sqrt(np.min(np.sum((rel - u[:, None] * directions) ** 2, axis=1))))


def _layer(robot: str, seed: int) -> MotionLayer:
    """The motion layer on the realistic plant, elastic with --elastic, less the features --without names."""
    if "gain" in WITHOUT:
        two_mass.TWIST_POSITION_OVER_VELOCITY = two_mass.POSITION_OVER_VELOCITY
    layer = make_virtual_motion_layer(robot, backend="servo", plant="realistic", seed=seed, elastic=ELASTIC[0],
                                      gear_feedforward=ELASTIC[0], gear_observer=OBSERVER[0],
                                      state_feedback=STATE_FEEDBACK[0], scaled_averaging=SCALED_AVERAGING[0])
    if "twist" in WITHOUT:
        layer.backend.loop.set_gear_twist(None)
        layer.backend.reset(np.array(layer.reference_q()))  # the rotors at the links' angles again
    if SMOOTHING_SHARE[0] is not None and layer.smoothing_s:
        cell = layer.backend.loop.cell
        layer.smoothing_s = two_mass.smoothing_windows_s(layer.kin.arm, cell.motor_inertia_kg_m2,
                                                         cell.plant.gear_stiffness_nm_rad, share=SMOOTHING_SHARE[0])
    if "smoothing" in WITHOUT:
        layer.smoothing_s = ()
    if "friction" in WITHOUT and layer.gear_friction is not None:
        layer.gear_friction.listener = None
        nominal = layer.gear_friction.warm_nm
        layer.backend.loop.servo.set_friction(*nominal)
    if "integral" in WITHOUT and layer.backend.loop.twist is not None:
        layer.backend.loop.twist.integral_of = None
        layer.backend.loop.twist.excess_of = None
    return layer


def _warm_up(layer: MotionLayer) -> None:
    """A robot that has run a while: the plant's gearboxes warm, and the controller told so."""
    layer.backend.loop.cell.warm_up()
    if layer.gear_friction is not None:
        layer.gear_friction.warm_up(layer.backend.loop.cell.gear_rise_k[0])


def run_moves(robot: str, seed: int, pvc: bool, cold: bool, carried_kg: float) -> dict[str, float]:
    """The fast moves; the worst distance of the TCP (from the measured angles through the model) from the programmed path.

    Elastic gears: the TCP from the links' own angles ("path_error_mm") and from the encoders less the
    commanded twist ("encoder_error_mm").
    """
    layer = _layer(robot, seed)
    loop = layer.backend.loop
    if not cold:
        _warm_up(layer)
    loop.set_payload(carried_kg, known=False)
    if LOAD_AT_REST[0]:   # as after a brake release: the gears wound under the load, the drives holding it
        layer.backend.reset(np.array(layer.reference_q()))
        for _ in range(round(REST_S / layer.dt_s)):
            layer.tick()   # no move: the motion cycle holds the reference
    worst, worst_moving, worst_encoder, steps, saturated = 0.0, 0.0, 0.0, 0, 0
    segments: list[np.ndarray] = []

    def measure() -> None:
        nonlocal worst, worst_moving, worst_encoder, steps, saturated
        if not segments:
            return
        steps += 1
        saturated += bool(loop.servo.saturated.any())
        fk = layer.kin.arm.fk_unchecked
        if ELASTIC[0]:
            distance = _distance(fk(loop.cell.link_q)[:3, 3], *segments)
            worst_encoder = max(worst_encoder, _distance(fk(loop.state().q)[:3, 3], *segments))
        else:
            distance = _distance(fk(loop.cell.q)[:3, 3], *segments)
        worst = max(worst, distance)
        if layer._settling is None:  # the reference still moves (not the FINE settling at the end)
            worst_moving = max(worst_moving, distance)

    loop.on_step.append(measure)
    nominal_s = actual_s = 0.0
    scaled_cycles = 0
    for target in TARGETS_DEG:
        h = layer.move(JointMotion(tuple(np.radians(target))), Params(load_kg=DECLARED_KG, path_velocity=pvc))
        segments[:] = _programmed_tcp(layer)
        nominal_end, controller = h.t_end_s, layer.pvc
        while layer._traj is not None and not h.done:  # until the reference reaches the end
            layer.tick()
        actual_s += layer.now_s() - h.start_time_s
        nominal_s += nominal_end - h.start_time_s
        scaled_cycles += controller.scaled_cycles if controller is not None else 0
        layer.wait(h)
        segments.clear()
    law = loop.state_feedback   # the motion cycles whose schedule made the gains again (the others kept them)
    made = law.scheduled / max(law.scheduled + law.kept, 1) if law is not None else 1.0
    return {"path_error_mm": worst * 1000.0, "moving_error_mm": worst_moving * 1000.0,
            "encoder_error_mm": worst_encoder * 1000.0,
            "saturated_fraction": saturated / max(steps, 1),
            "duration_ratio": actual_s / nominal_s, "scaled_cycles": float(scaled_cycles), "duration_s": actual_s,
            "gains_made_fraction": made}


def nominal_equals_actual(robot: str, seed: int) -> bool:
    """On a warm plant with the payload declared right, the reference is the nominal trajectory, sample for sample."""
    layer = _layer(robot, seed)
    loop = layer.backend.loop
    _warm_up(layer)
    loop.set_payload(DECLARED_KG, known=False)
    same = True
    for target in TARGETS_DEG:
        h = layer.move(JointMotion(tuple(np.radians(target))), Params(load_kg=DECLARED_KG))
        traj = layer._traj
        commanded = [layer.reference_q()]
        while layer._traj is traj and not h.done:
            layer.tick()
            commanded.append(layer.reference_q())
        if traj is not None:
            nominal = traj.q_f[:: traj.sub][: len(commanded)]
            same = same and len(commanded) == traj.cycles + 1 and bool(np.array_equal(np.array(commanded), nominal))
        layer.wait(h)
    return same


#: Moves that are not averaged (docs/robots.md, "Elastic gears"): short moves, zone blends, a stop from full speed;
#: and moves that are: FINE moves from rest (to the zone moves' targets).
SHORT_MOVES_RAD = ((0.01, -0.005, 0.008, 0.0, 0.0, 0.0), (-0.003, 0.004, -0.002, 0.01, 0.0, 0.0))
ZONE_TARGETS_DEG = ((40, -20, -30, 0, 30, 0), (-40, 20, -10, 30, 0, 0))
STOP_TARGET_DEG, STOP_AFTER_CYCLES = (120, 40, -30, 0, 30, 0), 200
SWING_FROM_S, SWING_CYCLES = 0.1, 250   #: the links' swing is measured from this long after the moves' end, this long


def swing_after(robot: str, seed: int, case: str) -> float:
    """The largest swing (mrad) of j1..j3's links from where they settle, from SWING_FROM_S after the moves of `case`
    ("short", "zone", "stop", "fine") end: ringing or hunting at rest. Cold plant, the load undeclared as in run_moves."""
    layer = _layer(robot, seed)
    loop, cell = layer.backend.loop, layer.backend.loop.cell
    loop.set_payload(CARRIED_KG, known=False)
    home, params = np.array(layer.reference_q()), Params(load_kg=DECLARED_KG)
    if case == "short":
        handles = [layer.move(JointMotion(tuple(home + np.array(d))), params) for d in SHORT_MOVES_RAD]
    elif case == "zone":
        handles = [layer.move(JointMotion(tuple(np.radians(t))), Params(load_kg=DECLARED_KG, zone_m=0.1))
                   for t in ZONE_TARGETS_DEG]
        handles.append(layer.move(JointMotion(tuple(home)), params))
    elif case == "fine":
        handles = [layer.move(JointMotion(tuple(np.radians(t))), params) for t in ZONE_TARGETS_DEG]
    else:
        handles = [layer.move(JointMotion(tuple(np.radians(STOP_TARGET_DEG))), params)]
        for _ in range(STOP_AFTER_CYCLES):
            layer.tick()
        layer.stop_move()
    for h in handles:
        layer.wait(h)
    end_s, after = cell.time_s, []
    link_q = (lambda: cell.link_q) if ELASTIC[0] else (lambda: cell.true_q)
    loop.on_step.append(lambda: after.append((link_q() - layer.reference_q())[:3].copy())
                        if cell.time_s > end_s + SWING_FROM_S else None)
    for _ in range(SWING_CYCLES):
        layer.tick()
    errors = np.array(after)
    return float(np.abs(errors - errors[-50:].mean(axis=0)).max()) * 1000.0


DUTY_CYCLES = 6   #: the thermal duty cycle: the fast moves this many times over, payload declared right


def thermal_estimate(robot: str, seed: int, corrected: bool = True) -> tuple[float, np.ndarray, np.ndarray]:
    """The winding-temperature estimate against the plant's windings after the duty cycle (error % of the rise).

    `corrected`: the estimate corrected from the drives' voltage and current (the default); False: the
    thermal model alone.
    """
    layer = _layer(robot, seed)
    if not corrected:
        layer.winding.measurement = None
    loop = layer.backend.loop
    _warm_up(layer)
    loop.set_payload(DECLARED_KG, known=False)
    for _ in range(DUTY_CYCLES):
        for target in TARGETS_DEG:
            layer.wait(layer.move(JointMotion(tuple(np.radians(target))), Params(load_kg=DECLARED_KG)))
    plant, estimate = loop.cell.winding_rise_k, layer.winding.rise_k
    heated = plant > 0.05 * plant.max()  # joints that carried load; a wrist at 0.1 K says nothing
    return float(np.max(np.abs(estimate - plant)[heated] / plant[heated]) * 100.0), plant, estimate


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robot", default="irb2400")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--elastic", action="store_true", help="elastic gears in the plant, the servo tuned for them")
    ap.add_argument("--observer", action="store_true",
                    help="with --elastic: the twist's extra torque from the gear-torque observer")
    ap.add_argument("--state-feedback", action="store_true",
                    help="with --elastic: the two-mass joints' state feedback (servo/state_feedback.py) instead of the cascade")
    ap.add_argument("--load-at-rest", action="store_true",
                    help="the carried load on the plant from the reset, the drives holding it REST_S before the moves")
    ap.add_argument("--without", action="append", default=[], choices=FEATURES,
                    help="with --elastic: switch off one of the elastic gears' features (repeatable)")
    ap.add_argument("--smoothing-share", type=float, default=None, metavar="SHARE",
                    help="with --elastic: average moves from rest over this share of the anti-resonance periods "
                         "(1: whole periods)")
    ap.add_argument("--scaled-averaging", action="store_true",
                    help="with --state-feedback: every move from rest averaged over the share of the whole windows its "
                         "steps' twist of the gears calls for")
    ap.add_argument("--inertia-tolerance", type=float, default=None, metavar="SHARE",
                    help="with --state-feedback: the state feedback's INERTIA_TOLERANCE for this run (default 0.02)")
    ap.add_argument("--gains-settled", type=float, default=None, metavar="SHARE",
                    help="with --state-feedback: its GAINS_SETTLED for this run (default 3e-2; inf: no cycle that only "
                         "settles the gains)")
    args = ap.parse_args()
    if (args.inertia_tolerance is not None or args.gains_settled is not None) and not args.state_feedback:
        ap.error("--inertia-tolerance and --gains-settled are the state feedback's (--state-feedback)")
    if args.inertia_tolerance is not None:
        state_feedback.INERTIA_TOLERANCE = args.inertia_tolerance
    if args.gains_settled is not None:
        state_feedback.GAINS_SETTLED = args.gains_settled
    ELASTIC[0] = args.elastic
    if args.smoothing_share is not None and not args.elastic:
        ap.error("--smoothing-share is for elastic gears (--elastic)")
    SMOOTHING_SHARE[0] = args.smoothing_share
    if args.observer and not args.elastic:
        ap.error("--observer is for elastic gears (--elastic)")
    OBSERVER[0] = args.observer
    if args.state_feedback and not args.elastic:
        ap.error("--state-feedback is for elastic gears (--elastic)")
    STATE_FEEDBACK[0] = args.state_feedback
    if args.scaled_averaging and not args.state_feedback:
        ap.error("--scaled-averaging is for the state feedback (--state-feedback)")
    SCALED_AVERAGING[0] = args.scaled_averaging
    LOAD_AT_REST[0] = args.load_at_rest
    WITHOUT.update(args.without)
    with_pvc = run_moves(args.robot, args.seed, True, True, CARRIED_KG)
    without = run_moves(args.robot, args.seed, False, True, CARRIED_KG)
    same = nominal_equals_actual(args.robot, args.seed)
    swings = {case: swing_after(args.robot, args.seed, case) for case in ("short", "zone", "stop", "fine")}
    thermal_pct, plant_rise, estimated_rise = thermal_estimate(args.robot, args.seed)
    model_only_pct, _, model_only_rise = thermal_estimate(args.robot, args.seed, corrected=False)
    print(f"robot={args.robot}")
    print(f"elastic={args.elastic}")
    if args.elastic:
        print(f"without={','.join(sorted(WITHOUT)) or 'none'}")
        print(f"observer={args.observer}")
        print(f"state_feedback={args.state_feedback}")
        layer = _layer(args.robot, args.seed)
        print(f"smoothing_windows_s={' '.join(f'{v:.3f}' for v in layer.smoothing_s) or 'none'}")
        print(f"smoothing_scaled_to_gear_steps={layer.planner.gear_steps is not None}")
        law = layer.backend.loop.state_feedback
        if law is not None:
            print(f"state_feedback_joints={' '.join(str(j + 1) for j in law.joints)}")
            print(f"state_feedback_link_bw_rad_s={law.bandwidth_rad_s:.1f}")
        gains = layer.backend.loop.servo.gains
        print(f"servo_velocity_bw_rad_s={' '.join(f'{v:.1f}' for v in gains.per_joint(len(gains.joint_velocity_bw_rad_s))[1])}")
        print(f"servo_position_gain_1_s={' '.join(f'{v:.1f}' for v in gains.per_joint(len(gains.joint_velocity_bw_rad_s))[0])}")
    print(f"load_at_rest={args.load_at_rest}")
    print(f"declared_load_kg={DECLARED_KG:g}")
    print(f"carried_load_kg={CARRIED_KG:g}")
    print(f"pvc_scaled_cycles={with_pvc['scaled_cycles']:.0f}")
    print(f"no_pvc_saturated_cycle_fraction={without['saturated_fraction']:.4f}")
    print(f"no_pvc_path_error_mm={without['path_error_mm']:.3f}")
    print(f"pvc_path_error_while_moving_mm={with_pvc['moving_error_mm']:.3f}")
    print(f"pvc_path_error_mm={with_pvc['path_error_mm']:.3f}")
    if args.elastic:
        print(f"no_pvc_encoder_path_error_mm={without['encoder_error_mm']:.3f}")
        print(f"pvc_encoder_path_error_mm={with_pvc['encoder_error_mm']:.3f}")
    if args.state_feedback:
        print(f"state_feedback_gains_made_fraction={with_pvc['gains_made_fraction']:.3f}")
    print(f"saturated_cycle_fraction={with_pvc['saturated_fraction']:.4f}")
    print(f"duration_ratio={with_pvc['duration_ratio']:.3f}")
    print(f"moves_duration_s={with_pvc['duration_s']:.3f}")
    print(f"nominal_equals_actual_when_feasible={same}")
    for case, swing in swings.items():
        print(f"links_swing_after_{case}_moves_mrad={swing:.4f}")
    print(f"plant_winding_rise_k={' '.join(f'{v:.2f}' for v in plant_rise)}")
    print(f"model_only_winding_rise_k={' '.join(f'{v:.2f}' for v in model_only_rise)}")
    print(f"thermal_estimate_error_pct_model_only={model_only_pct:.2f}")
    print(f"estimated_winding_rise_k={' '.join(f'{v:.2f}' for v in estimated_rise)}")
    print(f"thermal_estimate_error_pct={thermal_pct:.2f}")


if __name__ == "__main__":
    main()
