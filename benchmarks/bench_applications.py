"""Application benchmark: part identification (IDENTMOVE) over seeded trials, and the process figures of the demos,
on the realistic plant and then on the ideal one (its keys prefixed `ideal_`).

Run: python benchmarks/bench_applications.py [--trials 1000] [--seed 1] [--plant elastic-gears [--whole-periods]]
     [--only calibrate|seam|ident]

Identification. The motion toward the via point is simulated on the MuJoCo cell for every combination of part
mass (0, 0.3, 0.9, 2 kg: the demo's kinds), speed (the joints' limits, 0.5 m/s, 0.3 m/s) and via point (the
demo's TopPos, 300, 150 and 100 mm above the pick), recording q, q-dot and the motor torques over 0.2 s as
IDENTMOVE does (on elastic gears as long as IDENTMOVE records there, with its windows: identify_window). On the realistic plant (friction, noise, elasticity, the unknown dress pack, a cold start) each
via point and speed is one robot: a tare lift with nothing held, then the four masses one after the other, each
estimated with the tare; on the ideal plant each recording is a fresh robot, without a tare. Each trial takes
one recording at random and perturbs its torques with seeded draws inside the documented envelope: per joint a
constant model error and a Coulomb friction change (each uniform in +-ENVELOPE_NM, the friction with the sign of
the joint's velocity), a viscous friction change (uniform in +-ENVELOPE_NM per rad/s) and white noise of
NOISE_NM per sample (the tare gets noise only). The trial classifies the estimate with limits half way between
the kinds' masses, as the demo does, and is confident only when payload_estimation.confidence trusts it.
Printed: ident_correct_pct (among confident answers, target >= 99), ident_abstain_pct (target <= 5),
ident_false_confident (target 0); in the same run without the controller's friction warm-up estimate
(ident_untracked_*), without that and the noise-aware windows (ident_plain_*, the estimator of the release
before), and the estimator that IDENTMOVE used before that (least squares over the samples, no friction, no
offsets, no tare, always answering): ident_baseline_correct_pct; and the same
trials with the model error and friction changes ten times larger (outside the envelope): ident_outside_*.
On the realistic plant also what an empty gripper's estimate reads without a tare (ident_untared_empty_*_kg), the tared estimate's error on one robot lifting 0, 0.3, 0.9, 2, 0 kg after a tare,
cold and warmed up: ident_{cold,warm}_max_error_kg and its drift against the time since the tare (kg/s).

Process figures: the demos' outcomes as `orc run --plant P` reports them in its summary's process section
(deburr_plain_left_mm: the bulge a single force-controlled pass leaves, measured by CatchBulge with
max_passes = 0; spot_saving_per_spot_s: the demo against MOVE, Close, WAIT UNTIL WELD_OK, Open per spot;
spot_signal_error_ms: per weld after the first, the close signal's time minus the TCP's stop (as WELDMOVE
defines it, measured on the TCP every motion cycle) minus REACTION, the largest; seam_tuned_gain_pct: the RMS
reduction of the thesis weld with Tracking's gain against TRACKMOVE's standard gain); and CALIBRATE's settling
(12 kg the program did not declare, a 50 mm approach at 1.5 m/s) with the default gains, the fixed 1.5x boost
alone and the identified tuning: calibrate_vs_boost_settle_pct is what the identification adds to the boost; each
part of the identified tuning switched off in turn (calibrate_identified_without_*), and the boost with the identified
friction part only (calibrate_boost_with_identified_friction_*: what the rest of the identification adds to that);
`--only calibrate` prints these alone; on the realistic plant with
its elastic gears (calibrate_*) and with rigid gears (calibrate_rigid_*). `--plant elastic-gears` runs the realistic
part on the elastic gears under their feed-forward and the state feedback (`orc run --plant elastic-gears`; the
calibrate_* then with that servo, calibrate_rigid_* as before) and leaves the ideal plant out; with
`--whole-periods` every cell on the elastic gears (the benchmark's and those of the `orc run` it starts) averages
every move from rest over the gears' whole periods (make_virtual_motion_layer(..., scaled_averaging=False)) instead of
the share its steps call for (the default; docs/motion.md, "Averaging on elastic gears").
deburr_servo_force_*: how well the arm's own motor torques tell the grinding force (no force flange), see
servo_force_estimate; deburr_servo_force_baseline_* and deburr_servo_error_*: the same against a free-air pass at
the same s (the signature GRINDMOVE without a flange uses), see servo_baseline; deburr_arm_*: thesis_2_1 as it runs
(the arm presses), see arm_grinding; deburr_flange_*: thesis_2_1 with a force flange on its grinder.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from orc_rpl.application.features import payload_estimation
from orc_rpl.application.features.materials_handling_behaviour import LEAD_S, identify_window
from orc_rpl.application.features.payload_estimation import confidence, estimate
from orc_rpl.application.runtime import MotionRequest, Sample, run_to_end
from orc_rpl.executive.cell_robot import CellRobot
from orc_rpl.motion.gear_friction import SIGN_SMOOTH_RAD_S, change_since
from orc_rpl.servo.control import FRICTION_SMOOTH_RAD_S as SERVO_FRICTION_SMOOTH_RAD_S
from orc_rpl.world.pose import Pose

ROOT = Path(__file__).resolve().parents[1]
MASSES_KG = (0.0, 0.3, 0.9, 2.0)
LIMITS_KG = (0.15, 0.6, 1.45)        #: half way between the kinds
SPEEDS_M_S = (None, 0.5, 0.3)
TOOL = Pose(0.0, 0.0, 0.18)
PICK = Pose(0.8, -0.3, 0.45, 0.0, math.pi, 0.0)
VIAS = (Pose(0.9, 0.0, 0.9, 0.0, math.pi, 0.0), Pose(0.8, -0.3, 0.75, 0.0, math.pi, 0.0),
        Pose(0.8, -0.3, 0.6, 0.0, math.pi, 0.0), Pose(0.8, -0.3, 0.55, 0.0, math.pi, 0.0))
ENVELOPE_NM = 0.3                    #: model error and friction changes per joint (N m; N m s/rad for viscous)
NOISE_NM = 0.2                       #: torque noise per sample (N m)


def kind(mass_kg: float) -> int:
    return sum(mass_kg >= limit for limit in LIMITS_KG)


ELASTIC_GEARS = [False]   #: --plant elastic-gears: the realistic figures on the realistic plant with elastic gears
WHOLE_PERIODS = [False]   #: --whole-periods: elastic gears' moves from rest averaged over the whole periods


def cell_plant(plant: str) -> str:
    """The plant a simulated cell is made with for the benchmark's `plant` ("realistic" or "ideal")."""
    return "elastic-gears" if plant == "realistic" and ELASTIC_GEARS[0] else plant


def use_whole_periods() -> None:
    """Every virtual motion layer made on the elastic gears from now on (in this process) averaging every move from
    rest over the whole periods: the cell robots, CALIBRATE's and `orc run`'s all make theirs through `orc_rpl.motion`."""
    import orc_rpl.motion

    make = orc_rpl.motion.make_virtual_motion_layer

    def whole(*args: Any, **kwargs: Any) -> Any:
        return make(*args, **kwargs, scaled_averaging=False if kwargs.get("plant") == "elastic-gears" else None)
    orc_rpl.motion.make_virtual_motion_layer = whole  # type: ignore[assignment]


#: `orc run` in a process of its own with the whole periods (`python -c ORC_RUN_WHOLE run ...`)
ORC_RUN_WHOLE = (f"import sys; sys.path.insert(0, {str(Path(__file__).resolve().parent)!r}); "
                  "import bench_applications; bench_applications.use_whole_periods(); "
                  "from orc_rpl.cli import main; raise SystemExit(main())")


def recordings(plant: str) -> list[tuple[float, list[Sample], CellRobot, list[Sample] | None, Any]]:
    """One recording of IDENTMOVE's first 0.2 s (elastic gears: identify_window) per mass, speed and via point on the MuJoCo cell. On the ideal
    plant each on a fresh robot, without a tare. On the realistic plant one robot per via point and speed, as
    a program runs it: a tare lift with nothing held, then the four masses one after the other (about 2 s
    apart: the cold arm's friction falls in between), each with the tare and the controller's estimate of
    how the friction changed since the tare (motion.gear_friction; None without a tare or an estimate)."""
    out = []
    for via in VIAS:
        for speed in SPEEDS_M_S:
            robot = CellRobot.virtual(plant=cell_plant(plant))
            tare: list[Sample] | None = None
            tare_state = None
            for mass in ((None, *MASSES_KG) if plant == "realistic" else MASSES_KG):
                if plant == "ideal":
                    robot = CellRobot.virtual(plant=cell_plant(plant))
                samples = _lift(robot, via, speed, mass or 0.0)
                state = robot.friction_state()
                if mass is None:
                    tare, tare_state = samples, state
                else:
                    change = None if tare_state is None or state is None else change_since(tare_state, state)
                    out.append((mass, samples, robot, tare, change))
    return out


class Lift(list):  # type: ignore[type-arg]
    """IDENTMOVE's recording of one lift (Samples) and the window its estimate takes (identify_window)."""

    window: int = payload_estimation.WINDOW


def _lift(robot: CellRobot, via: Pose, speed: float | None, mass: float) -> Lift:
    """From the pick toward `via` holding `mass`: IDENTMOVE's recording (as long as IDENTMOVE records on this
    robot: longer on elastic gears, `identify_window`); the robot then goes back to the pick."""
    run_to_end(robot, MotionRequest("MOVE", "joint", PICK, tool=TOOL), 30.0, "to the pick")
    record_s, window = identify_window(robot, robot.joints())
    robot.set_plant_payload(mass)
    for _ in range(25):
        robot.tick()
    half = 0.5 * math.dist((PICK.x, PICK.y, PICK.z), (via.x, via.y, via.z))
    ticket = robot.submit(MotionRequest("IDENTMOVE", "joint", via, tool=TOOL, speed_m_s=speed,   # as IDENTMOVE asks
                                        zone_m=min(0.1, half), record_s=record_s, time_s=record_s + LEAD_S,
                                        whole_averaging=True))
    while not ticket.done:
        robot.tick()
    robot.set_plant_payload(0.0)
    lift = Lift(ticket.recording)
    lift.window = window
    return lift


def tare_drift(warm: bool) -> dict[str, float]:
    """One realistic robot (cold, or warmed up: gearboxes 30 K above ambient, which its controller then knows), a
    tare lift toward TopPos, then 0, 0.3, 0.9, 2 and 0 kg one after the other: the largest error of the tared
    estimate, and its drift (a least-squares line through the errors against the time since the tare, kg/s);
    with the controller's friction warm-up estimate (as IDENTMOVE runs) and without it (`_untracked`)."""
    robot = CellRobot.virtual(plant=cell_plant("realistic"))
    if warm:
        robot.layer.backend.loop.cell.warm_up()  # type: ignore[attr-defined]
        robot.layer.gear_friction.warm_up(30.0)  # type: ignore[attr-defined]
    tare = _lift(robot, VIAS[0], None, 0.0)
    tare_s, tare_state, ages = robot.time_s(), robot.friction_state(), []
    errors: dict[str, list[float]] = {"": [], "_untracked": []}
    for mass in (0.0, 0.3, 0.9, 2.0, 0.0):
        samples = _lift(robot, VIAS[0], None, mass)
        ages.append(samples[0].time_s - tare_s)
        change = change_since(tare_state, robot.friction_state())
        errors[""].append(estimate(samples, robot.inverse_dynamics, tare, change, samples.window).mass_kg - mass)
        errors["_untracked"].append(estimate(samples, robot.inverse_dynamics, tare, window=samples.window).mass_kg - mass)
    label = "warm" if warm else "cold"
    out = {}
    for variant, found in errors.items():
        out[f"ident_{label}{variant}_max_error_kg"] = round(max(abs(e) for e in found), 3)
        out[f"ident_{label}{variant}_drift_kg_s"] = round(float(np.polyfit(ages, found, 1)[0]), 4)
    return out


@contextlib.contextmanager
def plain_windows(on: bool) -> Iterator[None]:
    """The payload estimator's windows as before the realistic plant's speed noise was allowed for: accelerations
    from the measured speeds and the fixed switch threshold alone."""
    saved = payload_estimation.SPEED_NOISE_RAD_S, payload_estimation.NOISE_SPREADS
    if on:
        payload_estimation.SPEED_NOISE_RAD_S, payload_estimation.NOISE_SPREADS = math.inf, 0.0
    try:
        yield
    finally:
        payload_estimation.SPEED_NOISE_RAD_S, payload_estimation.NOISE_SPREADS = saved


def perturbed(samples: list[Sample], rng: np.random.Generator, scale: float) -> list[Sample]:
    n = len(samples[0].torque)
    error = rng.uniform(-1, 1, n) * ENVELOPE_NM * scale
    coulomb = rng.uniform(-1, 1, n) * ENVELOPE_NM * scale
    viscous = rng.uniform(-1, 1, n) * ENVELOPE_NM * scale
    out = []
    for s in samples:
        qd = np.array(s.qd)
        tau = (np.array(s.torque) + error + coulomb * np.sign(np.where(np.abs(qd) < 1e-3, 0.0, qd)) + viscous * qd
               + rng.normal(0.0, NOISE_NM, n))
        out.append(Sample(s.time_s, s.q, s.qd, tuple(tau.tolist())))
    return out


def baseline_estimate(samples: list[Sample], inverse_dynamics: object) -> float:
    """IDENTMOVE's estimator before: least squares over the samples after 40 ms, q-double-dot differentiated."""
    num = den = 0.0
    for i, s in enumerate(samples):
        if s.time_s - samples[0].time_s < 0.04 - 1e-9 or i == 0:
            continue
        dt = s.time_s - samples[i - 1].time_s
        qdd = tuple((a - b) / dt for a, b in zip(s.qd, samples[i - 1].qd))
        t0 = inverse_dynamics(s.q, s.qd, qdd, 0.0)  # type: ignore[operator]
        t1 = inverse_dynamics(s.q, s.qd, qdd, 1.0)  # type: ignore[operator]
        for m, a, b in zip(s.torque, t0, t1):
            num += (b - a) * (m - a)
            den += (b - a) ** 2
    return max(0.0, num / den) if den else 0.0


def identification(trials: int, seed: int, plant: str) -> dict[str, float]:
    started = time.perf_counter()
    base = recordings(plant)
    recorded_s = time.perf_counter() - started
    figures: dict[str, float] = {"ident_recordings": len(base), "ident_trials": trials,
                                 "ident_recording_wall_s": round(recorded_s, 1)}
    for label, scale in (("ident", 1.0), ("ident_outside", 10.0)):
        rng = np.random.default_rng(seed)
        # correct, abstain, wrong; _untracked: no friction warm-up estimate; _plain: neither that nor the noise-aware
        # windows (accelerations from the measured speeds, a fixed switch threshold): the estimator of the last release
        counts = {"": [0, 0, 0], "_untracked": [0, 0, 0], "_plain": [0, 0, 0]}
        baseline_correct = 0
        worst_sigma = 0.0
        for _ in range(trials):
            mass, samples, robot, tare, change = base[int(rng.integers(len(base)))]
            noisy = perturbed(samples, rng, scale)
            noisy_tare = None if tare is None else perturbed(tare, rng, 0.0)
            for variant, friction in (("", change), ("_untracked", None), ("_plain", None)):
                with plain_windows(variant == "_plain"):  # (the release before's estimator: WINDOW samples a window)
                    window = payload_estimation.WINDOW if variant == "_plain" else samples.window
                    found = estimate(noisy, robot.inverse_dynamics, noisy_tare, friction, window)
                answer, _, trusted = confidence(kind, found.mass_kg, found.sigma_kg)
                if not variant:
                    worst_sigma = max(worst_sigma, found.sigma_kg)
                counts[variant][1 if not trusted else 0 if answer == kind(mass) else 2] += 1
            baseline_correct += kind(baseline_estimate(noisy, robot.inverse_dynamics)) == kind(mass)
        for variant, (correct, abstain, wrong) in counts.items():
            if variant and plant != "realistic":
                continue  # the ideal plant has no tare and no warm-up estimate: the same figures
            confident = correct + wrong
            figures[f"{label}{variant}_correct_pct"] = round(100.0 * correct / confident, 2) if confident else float("nan")
            figures[f"{label}{variant}_abstain_pct"] = round(100.0 * abstain / trials, 2)
            figures[f"{label}{variant}_false_confident"] = wrong
        figures[f"{label}_baseline_correct_pct"] = round(100.0 * baseline_correct / trials, 2)
        figures[f"{label}_max_sigma_kg"] = round(worst_sigma, 3)
    if plant == "realistic":  # what the model's own errors read as without a tare: an empty gripper's estimate
        empty = [estimate(samples, robot.inverse_dynamics, window=samples.window).mass_kg
                 for mass, samples, robot, *_ in base if mass == 0.0]
        figures["ident_untared_empty_min_kg"] = round(min(empty), 2)
        figures["ident_untared_empty_max_kg"] = round(max(empty), 2)
        figures.update(tare_drift(warm=False))
        figures.update(tare_drift(warm=True))
    return figures


def demo_process(plant: str, program: str, change: tuple[str, str] | None = None) -> dict:
    """The `process` section of `orc run PROGRAM --summary-json` (the program's text changed by `change`)."""
    with tempfile.TemporaryDirectory() as folder:
        source = ROOT / program
        if change is not None:
            changed = Path(folder) / source.name
            text = source.read_text(encoding="utf-8")
            assert change[0] in text
            changed.write_text(text.replace(*change), encoding="utf-8")
            shutil.copy(source.with_suffix(".sim.yaml"), changed.with_suffix(".sim.yaml"))
            source = changed
        summary = Path(folder) / "summary.json"
        orc = ["-c", ORC_RUN_WHOLE] if WHOLE_PERIODS[0] else ["-m", "orc_rpl"]
        subprocess.run([sys.executable, *orc, "run", str(source), "--summary-json", str(summary),
                        "--plant", cell_plant(plant)], check=False, capture_output=True)
        return json.loads(summary.read_text()).get("process", {})


def spot_run(naive: bool, plant: str) -> tuple[float, list[float], float] | None:
    """demo_spot_welding.rpl on the cell (WELDMOVE, or MOVE then Close, WAIT UNTIL WELD_OK, Open): its cycle time,
    per weld the close signal's time minus (the TCP's actual stop minus REACTION), and the first weld's; None
    when the program did not finish (its error printed to standard error)."""
    from orc_rpl.application.standard_behaviour import runtime_registry
    from orc_rpl.executive.executive import Executive
    from orc_rpl.executive.sim_io import load_script
    from orc_rpl.syntax.parser import parse

    program = ROOT / "programs/online/demo_spot_welding.rpl"
    source = program.read_text(encoding="utf-8")
    if naive:
        weld = "WELDMOVE weldgun TO OFFS(first, 0, (i - 1) * pitch, 0)"
        assert weld in source
        source = source.replace(weld, "MOVE weldgun TO OFFS(first, 0, (i - 1) * pitch, 0)\n        weldgun.Close\n"
                                      "        WAIT UNTIL DigIn[2]\n        weldgun.Open")
    robot = CellRobot.virtual(plant=cell_plant(plant))
    executive = Executive(parse(source, str(program)), robot, runtime_registry(), path=str(program), source=source,
                          output=lambda line: None)
    script = load_script(program.with_suffix(".sim.yaml"), robot.io, lambda: robot.plant_tcp_pose(executive.machine.last_tool))
    ends: list[float] = []
    trace: list[tuple[float, tuple[float, float, float]]] = []
    submit, tick, tool = robot.submit, robot.tick, Pose(0, 0, 0.25)

    def noting_submit(request: MotionRequest) -> object:
        ticket = submit(request)
        if request.keyword == "WELDMOVE":
            ends.append(ticket.handles[0].t_end_s)
        return ticket

    def tracing_tick() -> None:
        tick()
        p = robot.tcp_pose(tool)
        trace.append((robot.time_s(), (p.x, p.y, p.z)))
    robot.submit = noting_submit  # type: ignore[method-assign]
    robot.tick = tracing_tick  # type: ignore[method-assign]
    executive.run()
    if executive.status != "finished":
        print(f"spot_run(naive={naive}, plant={cell_plant(plant)}): {executive.report()}", file=sys.stderr)
        return None
    gun, reaction_s = executive.machine.globals["weldgun"].behaviour, script.weld_guns[0].reaction_s
    errors = [signal - (_stop(trace, end) - reaction_s) for signal, end in zip(gun.signals, ends)]
    # the first weld of each kind (the approach from above, the first ShortMove) measures the arm's settling
    return robot.time_s(), errors[2:], max(errors[:2]) if errors else math.nan


def _stop(trace: list[tuple[float, tuple[float, float, float]]], from_s: float) -> float:
    """The TCP's actual stop near the reference's end `from_s` (from EARLY_S before it): the start of the first
    motion cycle from which its speed stays below STILL_SHARE of the gun's MAX_SPEED for STILL_WINDOW_S."""
    from orc_rpl.application.features.spot_welding_behaviour import EARLY_S, MAX_SPEED_M_S, STILL_SHARE, STILL_WINDOW_S

    moving = [math.dist(p, q) / (t - u) >= STILL_SHARE * MAX_SPEED_M_S for (u, q), (t, p) in zip(trace, trace[1:])]
    for i, (t, _) in enumerate(trace[:-1]):
        if t >= from_s - EARLY_S - 1e-9:
            j = i
            while j < len(moving) and trace[j][0] < t + STILL_WINDOW_S - 1e-9 and not moving[j]:
                j += 1
            if j < len(moving) and trace[j][0] >= t + STILL_WINDOW_S - 1e-9:
                return t
    return math.nan


def processes(plant: str) -> dict[str, float]:
    figures: dict[str, float] = {}
    grind = demo_process(plant, "programs/online/thesis_2_1_grindmove.rpl")
    figures["deburr_left_mm"] = round(1000 * max((b["left_m"] for b in grind.get("bulges", [])), default=math.nan), 3)
    figures["deburr_passes"] = sum(len(b["pass_heights_m"]) for b in grind.get("bulges", []))
    # the same casting with no grinding-down passes: what one force-controlled pass along the edge leaves
    plain = demo_process(plant, "programs/online/thesis_2_1_grindmove.rpl", ("max_passes = 4", "max_passes = 0"))
    figures["deburr_plain_left_mm"] = round(1000 * max((b["left_m"] for b in plain.get("bulges", [])),
                                                       default=math.nan), 3)
    # the same program with a force flange on the grinder (without one, the arm presses and feels the force)
    flange = demo_process(plant, "programs/online/thesis_2_1_grindmove.rpl", (GRINDER, GRINDER + FLANGE))
    figures["deburr_flange_left_mm"] = round(1000 * max((b["left_m"] for b in flange.get("bulges", [])),
                                                        default=math.nan), 3)
    figures["deburr_flange_passes"] = sum(len(b["pass_heights_m"]) for b in flange.get("bulges", []))
    weldmove, naive = spot_run(False, plant), spot_run(True, plant)
    figures["spot_weldmove_finished"] = weldmove is not None
    figures["spot_naive_finished"] = naive is not None
    if weldmove is not None and naive is not None:
        (weldmove_s, errors, first), naive_s = weldmove, naive[0]
        figures["spot_saving_per_spot_s"] = round((naive_s - weldmove_s) / (len(errors) + 2), 4)
        figures["spot_signal_error_ms"] = round(1000 * max(abs(x) for x in errors), 2)
        figures["spot_first_signal_error_ms"] = round(1000 * first, 2)  # the first welds measure the settling
    welds = demo_process(plant, "programs/online/demo_spot_welding.rpl").get("welds", [])
    figures["spot_good_welds"] = sum(w["good"] for w in welds)
    figures["spot_max_speed_at_close_mm_s"] = round(1000 * max((w["speed_m_s"] for w in welds), default=math.nan), 2)
    figures["spot_max_offset_at_close_mm"] = round(1000 * max((w["offset_m"] for w in welds), default=math.nan), 3)
    return {**figures, **seam_figures(plant)}


def seam_figures(plant: str) -> dict[str, float]:
    """The thesis weld (thesis_2_3_seam_tracking.rpl) with Tracking's gain and with TRACKMOVE's standard gain
    (`--only seam` prints these alone)."""
    figures: dict[str, float] = {}
    seams = demo_process(plant, "programs/online/thesis_2_3_seam_tracking.rpl").get("seams", [])
    figures["seam_rms_mm"] = round(1000 * max((s["rms_m"] for s in seams), default=math.nan), 3)
    figures["seam_max_mm"] = round(1000 * max((s["max_m"] for s in seams), default=math.nan), 3)
    figures["seam_gain"] = round(max((s["gain"] for s in seams), default=math.nan), 3)
    # the same weld without Tracking's gain (TRACKMOVE's standard low gain)
    untuned = demo_process(plant, "programs/online/thesis_2_3_seam_tracking.rpl",
                           ("  WITH TRACKING = OptTrack\n", "")).get("seams", [])
    figures["seam_untuned_rms_mm"] = round(1000 * max((s["rms_m"] for s in untuned), default=math.nan), 3)
    figures["seam_tuned_gain_pct"] = round(100 * (1 - figures["seam_rms_mm"] / figures["seam_untuned_rms_mm"]), 1)
    return figures


def servo_force_estimate(plant: str) -> dict[str, float]:
    """What GRINDMOVE would have without a force flange: the normal contact force estimated from the arm's own
    motor torques every motion cycle of thesis_2_1_grindmove.rpl (the flange variant grinds; the contact force
    acts on the arm), against the casting's true contact force. In contact: the error's RMS and maximum after the
    best constant tare (its median taken off). Without the casting (the same path, nothing touched): the
    estimate's peak-to-peak. Four models of the torque the arm needs: deburr_servo_force_* the servo's (rigid
    body at qdd = 0, declared payload, the NOMINAL friction smoothed as its feed-forward is); _sharp_* rigid body
    with the acceleration (from the encoder angles) and the nominal friction with a sharp Coulomb term
    (motion.gear_friction.SIGN_SMOOTH_RAD_S); _tracked_* that with the controller's friction warm-up estimate
    (motion.gear_friction); _plant_friction_* that with the plant's own friction coefficients (the bound of any
    identification of Coulomb and viscous friction)."""
    figures = {}
    names = ("", "_sharp", "_tracked", "_plant_friction")
    for casting_on in (True, False):
        rows = np.array(_torque_force_rows(plant, casting_on))
        for column, name in enumerate(names, start=1):
            if casting_on:
                contact = rows[rows[:, 0] > 0.0]
                error = contact[:, column] - contact[:, 0]
                error -= np.median(error)
                if not name:
                    figures["deburr_servo_force_true_mean_n"] = round(float(contact[:, 0].mean()), 1)
                figures[f"deburr_servo_force{name}_error_rms_n"] = round(float(np.sqrt(np.mean(error ** 2))), 1)
                figures[f"deburr_servo_force{name}_error_max_n"] = round(float(np.abs(error).max()), 1)
            else:
                figures[f"deburr_servo_force{name}_free_p2p_n"] = round(float(np.ptp(rows[:, column])), 1)
    return figures


def _torque_force_rows(plant: str, casting_on: bool) -> list[tuple[float, ...]]:
    """(true contact force, then the force estimated with each model of servo_force_estimate) every motion cycle of
    the grinding moves of thesis_2_1_grindmove (without a warm-up estimate, the tracked and plant columns are the
    sharp one)."""
    program = ROOT / "programs/online/thesis_2_1_grindmove.rpl"
    rows: list[tuple[float, ...]] = []
    source = program.read_text(encoding="utf-8")
    assert GRINDER in source
    source = source.replace(GRINDER, GRINDER + FLANGE)  # the flange grinds, the contact force acts on the arm

    def row(robot: CellRobot, estimator: TorqueForce, castings: list[Any], loop: Any, s: float) -> None:
        rows.append((sum(c.force_n for c in castings), *estimator.estimates()))  # the casting's normal is +z
    _grinding_run(plant, program, source, casting_on, row)
    return rows


#: The baseline (signature) passes: GRINDMOVE along the thesis_2_1 edge lifted BASELINE_OFFSET_MM off the part with
#: no force (the stroke stays at 0: free air), twice, then twice on the edge at 30 N (the flange holds the force,
#: the arm follows the nominal path and feels the contact); no bulge is caught (tolerance 100 mm), every pass the
#: same direction, speed and ends. BASELINE_WINDOW: the residual also averaged over this many motion cycles (40 ms,
#: 4 mm at 100 mm/s, a tenth of the demo's bulge).
BASELINE_OFFSET_MM = 5.0
#: thesis_2_1's grinder, and the force flange these measurements give it (without one GRINDMOVE presses with the arm)
GRINDER = "INSTALL grinder AS Grinder WITH SPINDLE = DigOut[5]"
FLANGE = " WITH FORCE_IN = AnalogIn[8] WITH STROKE = AnalogOut[8]"
BASELINE_WINDOW = 10


def arm_grinding(plant: str) -> dict[str, float]:
    """thesis_2_1_grindmove.rpl as it runs by default (no force flange: the arm presses and reads the force from
    its motor torques against a free-air signature): every cycle of its force loop in contact moves, the casting's
    true contact force against the command from the first cycle within 20 % of it on (deburr_arm_force_error_rms_n,
    _max_n, over the bulge's flanks too)
    and against the arm's estimate (deburr_arm_estimate_error_rms_n, _max_n), and the highest burr left on the
    casting itself (deburr_arm_casting_left_mm, not CatchBulge's measurement)."""
    from orc_rpl.application.features import deburring_arm
    from orc_rpl.application.standard_behaviour import runtime_registry
    from orc_rpl.executive.executive import Executive
    from orc_rpl.executive.sim_io import load_script
    from orc_rpl.syntax.parser import parse

    program = ROOT / "programs/online/thesis_2_1_grindmove.rpl"
    source = program.read_text(encoding="utf-8")
    robot = CellRobot.virtual(plant=cell_plant(plant))
    executive = Executive(parse(source, str(program)), robot, runtime_registry(), path=str(program),
                          source=source, output=lambda line: None)
    castings = load_script(program.with_suffix(".sim.yaml"), robot.io,
                           lambda: robot.plant_tcp_pose(executive.machine.last_tool), robot.set_plant_payload,
                           robot.push_on_arm).castings
    step = deburring_arm.ArmForceLoop.step
    rows: list[tuple[float, float, float]] = []

    def recording_step(loop: Any, s: float, arc_m: float) -> tuple[float, float]:
        command, measured = step(loop, s, arc_m)
        rows.append((sum(c.force_n for c in castings), command, measured))
        return command, measured
    deburring_arm.ArmForceLoop.step = recording_step  # type: ignore[method-assign]
    try:
        executive.run()
    finally:
        deburring_arm.ArmForceLoop.step = step  # type: ignore[method-assign]
    table = np.array(rows)
    table = table[int(np.argmax(np.abs(table[:, 0] - table[:, 1]) <= 0.2 * table[:, 1])):]  # from the first contact
    error, estimate = table[:, 0] - table[:, 1], table[:, 2] - table[:, 0]
    return {"deburr_arm_status_finished": int(executive.status == "finished"),
            "deburr_arm_force_error_rms_n": round(float(np.sqrt(np.mean(error ** 2))), 1),
            "deburr_arm_force_error_max_n": round(float(np.abs(error).max()), 1),
            "deburr_arm_estimate_error_rms_n": round(float(np.sqrt(np.mean(estimate ** 2))), 1),
            "deburr_arm_estimate_error_max_n": round(float(np.abs(estimate).max()), 1),
            "deburr_arm_casting_left_mm": round(1000 * max(c.max_height_m() for c in castings), 3)}


def servo_baseline(plant: str) -> dict[str, float]:
    """Does the arm's own signal repeat pass after pass at the same s, so that a baseline cancels it? The tracked
    torque estimate of the normal force (servo_force_estimate's best model without the plant's truth) and the
    servo's position error along the normal, each minus the same signal of an earlier pass interpolated at the same
    s. Printed: the first contact pass against the second free-air pass (the force's residual against the true
    contact force, per cycle and averaged over BASELINE_WINDOW cycles: deburr_servo_force_baseline_error_*), the
    second free-air pass against the first (truth 0: _baseline_free_*), and the servo error's residual between the
    free-air passes (deburr_servo_error_baseline_*_mm) against what pressing with 30 N shifts it by
    (deburr_servo_error_contact_shift_mm, the median over the contact pass)."""
    program = ROOT / "programs/online/thesis_2_1_grindmove.rpl"

    def path(z_mm: float) -> str:
        return "[" + ", ".join(f"POSE(900mm, {y}mm, {z_mm}mm, 0, 180deg, 0)" for y in (-200, 0, 200)) + "]"
    grind = "GRINDMOVE grinder ALONG {} WITH DEBURRING = pars WITH VELOCITY = 100mm/s WITH FORCE = {}N\n"
    source = (f"TOOL grinder = POSE(0, 0, 150mm, 0, 0, 0)\n{GRINDER}{FLANGE}\n"
              f"PATH free = {path(600 + BASELINE_OFFSET_MM)}\nPATH edge = {path(600)}\n"
              "VAR pars = GrindingPars(tolerance = 100mm, max_passes = 0)\n"
              + 2 * grind.format("free", 0) + 2 * grind.format("edge", 30))
    rows: list[tuple[float, ...]] = []
    loops: list[Any] = []  # the loops themselves, kept alive: a finished loop's id() may be a later loop's

    def row(robot: CellRobot, estimator: TorqueForce, castings: list[Any], loop: Any, s: float) -> None:
        if not loops or loops[-1] is not loop:  # a new GRINDMOVE: a new pass
            loops.append(loop)
        rows.append((len(loops) - 1, s, sum(c.force_n for c in castings), estimator.estimates()[2],
                     estimator.servo_error_m()))
    _grinding_run(plant, program, source, True, row)
    table = np.array(rows)
    free1, free2, contact = (table[table[:, 0] == k] for k in range(3))

    def residual(a: np.ndarray, b: np.ndarray, column: int) -> np.ndarray:
        """a's signal minus b's at a's s (b sorted by s), less the change of the true force."""
        order = np.argsort(b[:, 1])
        change = a[:, 2] - np.interp(a[:, 1], b[order, 1], b[order, 2]) if column == 3 else 0.0
        return a[:, column] - np.interp(a[:, 1], b[order, 1], b[order, column]) - change

    def averaged(x: np.ndarray) -> np.ndarray:
        return np.convolve(x, np.ones(BASELINE_WINDOW) / BASELINE_WINDOW, mode="valid")
    figures: dict[str, float] = {}
    for name, (a, b) in (("", (contact, free2)), ("_free", (free2, free1))):
        error = residual(a, b, 3)
        figures[f"deburr_servo_force_baseline{name}_error_rms_n"] = round(float(np.sqrt(np.mean(error ** 2))), 1)
        figures[f"deburr_servo_force_baseline{name}_error_max_n"] = round(float(np.abs(error).max()), 1)
        smooth = averaged(error)
        figures[f"deburr_servo_force_baseline{name}_error_rms_{BASELINE_WINDOW}_n"] = round(
            float(np.sqrt(np.mean(smooth ** 2))), 1)
        figures[f"deburr_servo_force_baseline{name}_error_max_{BASELINE_WINDOW}_n"] = round(float(np.abs(smooth).max()), 1)
    servo = residual(free2, free1, 4)
    figures["deburr_servo_error_baseline_rms_mm"] = round(1000 * float(np.sqrt(np.mean(servo ** 2))), 4)
    figures["deburr_servo_error_baseline_max_mm"] = round(1000 * float(np.abs(servo).max()), 4)
    figures["deburr_servo_error_contact_shift_mm"] = round(1000 * float(np.median(residual(contact, free2, 4))), 4)
    return figures


class TorqueForce:
    """The normal (+z) force on the TCP estimated from the arm's motor torques with the models of
    servo_force_estimate, once a motion cycle (the acceleration from the last three cycles' encoder angles)."""

    def __init__(self, robot: CellRobot, tool: Any) -> None:
        self.robot, self.tool = robot, tool
        self.gears = getattr(robot.layer, "gear_friction", None)
        self.servo = robot.layer.backend.loop.servo  # type: ignore[attr-defined]
        self.nominal = (np.zeros(6), np.zeros(6)) if self.gears is None else self.gears.warm_nm
        self.angles: list[tuple[float, np.ndarray]] = []

    def estimates(self) -> list[float]:
        """The servo model's, _sharp's, _tracked's and _plant_friction's estimate now (N)."""
        robot, nominal = self.robot, self.nominal
        q, qd = robot.joints(), robot.joint_speeds()
        external = np.array(robot.model_torques(q, qd)) - np.array(robot.torques())
        jacobian_t = robot.jacobian_linear(self.tool()).T
        force = np.linalg.lstsq(jacobian_t, external, rcond=None)[0]
        self.angles[:] = [*self.angles[-2:], (robot.time_s(), np.array(q))]
        qdd = np.zeros(len(q))
        if len(self.angles) == 3 and self.angles[2][0] - self.angles[0][0] > 0:
            (t0, q0), (t1, q1), (t2, q2) = self.angles
            qdd = ((q2 - q1) / (t2 - t1) - (q1 - q0) / (t1 - t0)) / (0.5 * (t2 - t0))
        speed = np.array(qd)
        # the servo's own model (its payload) with the acceleration, its nominal friction feed-forward taken out
        rigid = (self.servo.model_torque(np.array(q), speed, qdd)
                 - nominal[0] * np.tanh(speed / SERVO_FRICTION_SMOOTH_RAD_S) - nominal[1] * speed
                 - np.array(robot.torques()))
        sign = np.tanh(speed / SIGN_SMOOTH_RAD_S)
        estimates = [float(force[2])]
        frictions = [nominal[0] * sign + nominal[1] * speed]
        if self.gears is not None:
            coulomb, viscous = robot.layer.backend.loop.cell.friction_nm()  # type: ignore[attr-defined]
            frictions += [self.gears.torque_nm(speed), coulomb * sign + viscous * speed]
        else:
            frictions += frictions * 2
        for friction in frictions:
            estimates.append(float(np.linalg.lstsq(jacobian_t, rigid + friction, rcond=None)[0][2]))
        return estimates

    def servo_error_m(self) -> float:
        """The servo's position error along the normal: +z of J (q_ref - q), m (commanded above measured > 0)."""
        robot = self.robot
        error = robot.layer.reference_q() - np.array(robot.joints())
        return float((robot.jacobian_linear(self.tool()) @ error)[2])


def _grinding_run(plant: str, program: Path, source: str, casting_on: bool,
                  row: Any) -> None:
    """Run `source` (GRINDMOVEs) on a fresh robot with the casting of `program`'s .sim.yaml (or none), calling
    row(robot, estimator, castings, loop, s) once a grinding cycle, before the force loop's step."""
    from orc_rpl.application.features import deburring_flange
    from orc_rpl.application.standard_behaviour import runtime_registry
    from orc_rpl.executive.executive import Executive
    from orc_rpl.executive.sim_io import load_script
    from orc_rpl.syntax.parser import parse

    robot = CellRobot.virtual(plant=cell_plant(plant))
    executive = Executive(parse(source, str(program)), robot, runtime_registry(), path=str(program),
                          source=source, output=lambda line: None)
    machine = executive.machine
    castings = load_script(program.with_suffix(".sim.yaml"), robot.io, lambda: robot.plant_tcp_pose(machine.last_tool),
                           robot.set_plant_payload, robot.push_on_arm).castings if casting_on else []
    estimator = TorqueForce(robot, lambda: machine.last_tool)
    sample = deburring_flange.ForceLoop.step

    def recording_step(loop: Any, s: float, arc_m: float = 0.0) -> tuple[float, float]:  # once a grinding cycle
        row(robot, estimator, castings, loop, s)
        return sample(loop, s, arc_m)
    deburring_flange.ForceLoop.step = recording_step  # type: ignore[method-assign]
    try:
        executive.run()
    finally:
        deburring_flange.ForceLoop.step = sample  # type: ignore[method-assign]


#: The variants of the tuning comparison: the default gains, the fixed boost alone, the identified tuning, and the
#: identified tuning with one part switched off (assembly_behaviour.PARTS), to credit each part its effect.
TUNING_VARIANTS = ("default", "boost", "identified", "identified_without_load", "identified_without_friction",
                   "identified_without_placement", "identified_without_inertia", "identified_without_feedforward",
                   "boost_with_identified_friction")


def settle_ms(variant: str, plant: str, elastic: bool = False) -> float:
    """After CALIBRATE with 12 kg the program did not declare, the 50 mm approach at 1.5 m/s: ms from the end of
    the reference until the TCP stays within 0.05 mm, with the default gains, the fixed boost only (BOOST times
    the robot's own per-joint gains, no feed-forward), or the identified tuning (whole, or with a part left out)."""
    from orc_rpl.application.features.assembly_behaviour import BOOST, identify
    from orc_rpl.application.standard_behaviour import runtime_registry
    from orc_rpl.executive.executive import Executive
    from orc_rpl.motion import make_virtual_motion_layer
    from orc_rpl.servo.control import ServoTuning
    from orc_rpl.syntax.parser import parse

    program = ROOT / "programs/online/thesis_2_4_calibrate.rpl"
    source = program.read_text(encoding="utf-8")
    # elastic gears with --plant elastic-gears: their whole servo (feed-forward, state feedback), else the cascade
    robot = CellRobot(make_virtual_motion_layer(plant=cell_plant(plant) if elastic else plant,
                                                elastic=elastic and not ELASTIC_GEARS[0]))
    robot.layer.backend.loop.set_payload(12.0, known=False)  # type: ignore[attr-defined]
    executive = Executive(parse(source, str(program)), robot, runtime_registry(), path=str(program),
                          source=source, output=lambda line: None)
    recordings: list[Any] = []
    identify_once = identify

    def recording_identify(recorded: Any, *args: Any, **kwargs: Any) -> Any:  # keep what CALIBRATE measured
        recordings.append((recorded, args, kwargs))
        return identify_once(recorded, *args, **kwargs)
    import orc_rpl.application.features.assembly_behaviour as assembly
    assembly.identify = recording_identify  # type: ignore[assignment]
    try:
        executive.run()
    finally:
        assembly.identify = identify_once  # type: ignore[assignment]
    gains, n = robot.servo_gains(), len(robot.joints())
    kp, bw = gains.per_joint(n)
    zero = (0.0,) * n
    tuning: Any = None
    if variant == "boost":
        tuning = ServoTuning(tuple(kp * BOOST), tuple(bw * BOOST), (gains.integral_bw_rad_s,) * n, zero, zero, zero,
                             "boost only")
    elif variant == "identified":
        tuning = executive.machine.globals["BoltTuning"]
    elif variant == "boost_with_identified_friction":   # the simplest alternative to the identification's other parts
        found = executive.machine.globals["BoltTuning"]
        tuning = ServoTuning(tuple(kp * BOOST), tuple(bw * BOOST), (gains.integral_bw_rad_s,) * n, zero, zero, zero,
                             "boost with the identified friction", friction_factor=found.friction_factor,
                             friction_smooth_rad_s=found.friction_smooth_rad_s)
    elif variant.startswith("identified_without_"):
        recorded, args, kwargs = recordings[-1]
        tuning = identify_once(recorded, *args, **kwargs, leave_out=frozenset({variant.split("_without_")[1]}))
    tool, target = Pose(0, 0, 0.12), Pose(0.95, 0, 0.65, 0, math.pi, 0)
    ticket = robot.submit(MotionRequest("MOVE", "joint", target, tool=tool, speed_m_s=1.5, tuning=tuning))
    last_outside_s = t_end_s = None
    for _ in range(5000):  # to the reference's end, then 0.6 s more
        robot.tick()
        p = robot.tcp_pose(tool)
        if math.dist((p.x, p.y, p.z), (target.x, target.y, target.z)) > 5e-5:
            last_outside_s = robot.time_s()
        if ticket.done and t_end_s is None:
            t_end_s = ticket.handles[0].t_end_s
        if t_end_s is not None and robot.time_s() > t_end_s + 0.6:
            break
    assert t_end_s is not None and last_outside_s is not None
    return round(1000.0 * max(0.0, last_outside_s - t_end_s), 1)


def tuning(plant: str) -> dict[str, float]:
    """The tuning comparison; on the realistic plant with its elastic gears (`calibrate_*`) and with rigid gears
    (`calibrate_rigid_*`), on the ideal plant rigid (printed with the ideal_ prefix)."""
    figures: dict[str, float] = {}
    for elastic, key in (((True, "calibrate"), (False, "calibrate_rigid")) if plant == "realistic"
                         else ((False, "calibrate"),)):
        settle = {variant: settle_ms(variant, plant, elastic) for variant in TUNING_VARIANTS}
        for variant, value in settle.items():
            figures[f"{key}_{variant}_settle_ms"] = value
        boost, identified = settle["boost"], settle["identified"]
        figures[f"{key}_vs_boost_settle_pct"] = round(100.0 * (boost - identified) / boost, 1) if boost else 0.0
    return figures


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=1000)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--plant", choices=("realistic", "elastic-gears"), default="realistic",
                        help="the plant of the figures without a prefix (default: realistic, as orc run makes it; "
                             "elastic-gears: the realistic plant with elastic gears, without the ideal_ figures)")
    parser.add_argument("--only", choices=("calibrate", "seam", "ident"), default=None,
                        help="only these figures, for working on one of them (calibrate: CALIBRATE's tuning "
                             "comparison, tuning(), a minute or two; seam: the thesis weld, seam_*; ident: the "
                             "identification of parts, ident_*)")
    parser.add_argument("--whole-periods", action="store_true",
                        help="with --plant elastic-gears: every move from rest averaged over the gears' whole periods "
                             "(make_virtual_motion_layer(..., scaled_averaging=False)), not the share its steps call for")
    args = parser.parse_args()
    if args.whole_periods and args.plant != "elastic-gears":
        parser.error("--whole-periods is for --plant elastic-gears")
    ELASTIC_GEARS[0] = args.plant == "elastic-gears"
    WHOLE_PERIODS[0] = args.whole_periods
    if args.whole_periods:
        use_whole_periods()
    print(f"plant={args.plant}", flush=True)
    if ELASTIC_GEARS[0]:
        print(f"scaled_averaging={not args.whole_periods}", flush=True)
    # the ideal plant's figures do not depend on --plant: printed with the default only
    for plant, prefix in (("realistic", ""),) + ((("ideal", "ideal_"),) if not ELASTIC_GEARS[0] else ()):
        if args.only == "calibrate":
            figures = tuning(plant)
        elif args.only == "seam":
            figures = seam_figures(plant)
        elif args.only == "ident":
            figures = identification(args.trials, args.seed, plant)
        else:
            figures = {**identification(args.trials, args.seed, plant), **processes(plant),
                       **servo_force_estimate(plant), **servo_baseline(plant), **arm_grinding(plant), **tuning(plant)}
        for key, value in figures.items():
            print(f"{prefix}{key}={value}", flush=True)


if __name__ == "__main__":
    main()
