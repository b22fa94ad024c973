"""Motion-core benchmark: simulation speed, time optimality, gain over a naive profile, LMOVE path accuracy.

Run: python benchmarks/bench_motion.py [--robot irb2400] [--seconds 60]
The last lines are `key=value` figures (targets: sim_speed_x_realtime >= 50,
sim_vs_raw_mujoco_ratio >= 0.25, time_optimality_ratio <= 1.03, vs_naive_ratio <= 0.8,
lmove_path_deviation_mm <= 1). The speed is the realistic plant's (median of five runs, each
against raw mj_step of the ideal arm); the other figures are the realistic plant's, warm, with the
payload declared right. sim_vs_raw_mujoco_ratio_python_servo_law is the same stack with the servo
law in Python (the reference the drives' law in C is tested against), measured alike;
sim_vs_raw_mujoco_ratio_numpy_bookkeeping is the stack with the per-cycle bookkeeping in numpy
instead of the compiled kernels (numba, orc_rpl/plant/compiled.py), measured alike.
sim_vs_raw_mujoco_ratio_elastic_gear_feedforward and _elastic_state_feedback are the same stack on the
elastic gears (opt-in: the cascade with the gears' twist fed forward; the slow joints under state
feedback, servo/state_feedback.py), measured alike; _elastic_state_feedback_python_loop is the state
feedback's motion cycle as the Python loop the one kernel of servo/state_feedback_cycle_kernels.py is
tested against (the law's own kernels on). motion_layer_ms_per_sim_s (and _elastic_state_feedback) is
the wall time per simulated second spent above the servo (the motion layer's cycle, recording and planning; the
median run of each), servo_plant_ms_per_sim_s_elastic_state_feedback the rest (the servo, the plant and mj_step).
--only elastic_state_feedback: the state feedback's five runs alone (its ratio, the raw mj_step it is measured
against, and the two parts of its wall time), for profiling that variant, each run followed by one with MuJoCo's
default constraint solver for the joints' friction (Newton with islands instead of the plant's PGS without them,
orc_rpl/plant/realistic.py), suffixed _newton_friction_solver; and elastic_plant_mj_step_us, a step of the elastic
plant alone (mujoco.rollout, the best of 21 rollouts of 10 000 steps), with the plant's solver and with the others of
STEP_SOLVERS (_without_friction_rows: the rows switched off, what they cost: not a plant). --only optimality: the
optimality figures alone. On a robot with elastic gears (IRB 2400) the optimality figures are printed for them too, under their state
feedback (`--plant elastic-gears`), warm, the payload declared right, suffixed _elastic_state_feedback (the LMOVE
deviation at the links' own angles), with the layer's averaging of moves from rest (each over as much of the
anti-resonance periods as its steps twist the gears) and, in the same run, suffixed _whole_periods, every move over the
whole periods (scaled_averaging=False) and, suffixed _no_averaging, without averaging (what the averaging costs in time).
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from orc_rpl.motion import CartesianMotion, JointMotion, MotionLayer, Params, make_virtual_motion_layer
from orc_rpl.motion.planner import TORQUE_SHARE
from orc_rpl.motion.timing import toppra_profile
from orc_rpl.motion.trajectory import SplinePath, segment_times
from orc_rpl.plant import realistic
from orc_rpl.plant.compiled import AVAILABLE, use_kernels
from orc_rpl.robot.plants import has_elastic_gears
from orc_rpl.world.pose import Pose

FINE_GRID_POINTS = 2000  #: grid of the reference TOPP-RA solution (the planner uses 40..200)


def offsets(layer: MotionLayer, dx: float, dy: float, dz: float) -> Pose:
    p = Pose.from_matrix(layer.fk(layer.kin.arm.home_q))
    return Pose(p.x + dx, p.y + dy, p.z + dz, p.a, p.b, p.c)


def joint_targets(layer: MotionLayer) -> list[np.ndarray]:
    home = np.array(layer.kin.arm.home_q)
    deltas = [
        [0.8, 0.3, -0.2, 0.5, -0.3, 1.0],
        [-0.6, -0.2, 0.3, -0.8, 0.4, -1.5],
        [1.5, 0.1, 0.1, 0.0, 0.2, 0.5],
        [0.3, -0.4, 0.4, 1.2, -0.5, 0.0],
        [-1.2, 0.35, -0.3, -0.4, 0.3, 2.0],
    ]
    return [home + np.array(d) for d in deltas]


def long_joint_targets(layer: MotionLayer) -> list[np.ndarray]:
    """Base swings of a palletising cell: long moves where the speed limits, not the accelerations, dominate."""
    home = np.array(layer.kin.arm.home_q)
    return [home + np.array(d) for d in ([2.6, 0.2, -0.1, 0.5, 0.3, 1.0], [-2.6, 0.3, 0.0, -0.5, -0.2, -1.0])]


def cart_targets(layer: MotionLayer) -> list[Pose]:
    return [offsets(layer, *d) for d in [(0.0, 0.4, -0.2), (-0.2, -0.3, -0.3), (0.1, 0.3, 0.1), (-0.25, 0.0, -0.35), (0.05, -0.45, 0.0)]]


def program_step(layer: MotionLayer, i: int) -> None:
    """One block of the mixed program, issued the way the executive will: zone moves look ahead by one."""
    joints, carts = joint_targets(layer), cart_targets(layer)
    home = np.array(layer.kin.arm.home_q)
    steps = [
        (JointMotion(tuple(joints[i % 5])), Params(zone_m=0.05)),
        (JointMotion(tuple(home)), Params()),
        (CartesianMotion(carts[i % 5]), Params(zone_m=0.02)),
        (CartesianMotion(carts[(i + 1) % 5]), Params(zone_m=0.02, speed_m_s=0.8)),
        (CartesianMotion(offsets(layer, 0.0, -0.1, -0.1)), Params(zone_m=0.01)),
        (CartesianMotion(offsets(layer, 0.0, 0.1, -0.1), "circular", via=offsets(layer, 0.1, 0.0, -0.1)), Params()),
        (CartesianMotion(offsets(layer, 0.0, 0.0, 0.0)), Params(load_kg=10.0)),
    ]
    for motion, params in steps:
        h = layer.move(motion, params)
        if params.zone_m > 0:
            layer.wait_for_room(1)
        else:
            layer.wait(h)


def warm_realistic(robot: str, plant: str = "realistic", averaging: str = "default") -> MotionLayer:
    """The realistic plant after a warm-up (friction about its warm value), no payload (none declared).

    `plant` "elastic-gears": with the elastic gears under their state feedback, the controller's gearbox estimate
    told of the warm-up too; `averaging` of the moves from rest there: "default" (the layer's: over as much of the
    anti-resonance periods as each move's steps twist the gears, `scaled_averaging`), "whole" (every move over the
    whole periods: `scaled_averaging=False`) or "none".
    """
    layer = make_virtual_motion_layer(robot, backend="servo", plant=plant,
                                      scaled_averaging=False if averaging == "whole" else None)
    layer.backend.loop.cell.warm_up()
    if layer.gear_friction is not None and plant == "elastic-gears":
        layer.gear_friction.warm_up(layer.backend.loop.cell.gear_rise_k[0])
    if averaging == "none":
        layer.smoothing_s = ()
    return layer


def bench_speed(robot: str, seconds: float, compiled: bool = True, kernels: bool = True,
                **plant: bool) -> tuple[float, float, float, float]:
    """(x real time of the whole stack, x real time of raw mj_step, their ratio, share of wall time in servo+plant).

    `compiled`: the servo law in the drives (C, the default); False: the Python law it is written from.
    `kernels`: the per-cycle bookkeeping compiled (the default where numba is installed); False: numpy.
    `plant`: make_virtual_motion_layer's elastic-gear keywords (elastic, gear_feedforward, state_feedback).
    """
    before = use_kernels(kernels)
    try:
        return _bench_speed(robot, seconds, compiled, plant)
    finally:
        use_kernels(before)


def _bench_speed(robot: str, seconds: float, compiled: bool, plant: dict[str, bool]) -> tuple[float, float, float, float]:
    layer = make_virtual_motion_layer(robot, backend="servo", record=True, plant="realistic", **plant)
    program_step(layer, 0)  # warm-up: imports (toppra pulls in matplotlib), caches
    layer = make_virtual_motion_layer(robot, backend="servo", record=True, plant="realistic", **plant)
    layer.backend.loop.use_compiled_law(compiled)
    below = [0.0]
    advance = layer.backend.advance

    def timed_advance(q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> None:
        t = time.perf_counter()
        advance(q, qd, qdd)
        below[0] += time.perf_counter() - t

    layer.backend.advance = timed_advance  # type: ignore[method-assign]
    t0 = time.perf_counter()
    i = 0
    while layer.now_s() < seconds:
        program_step(layer, i)
        i += 1
    wall = time.perf_counter() - t0
    ours = layer.now_s() / wall

    import mujoco

    from orc_rpl.plant import build_spec, default_cell

    model = build_spec(default_cell(robot)).compile()
    data = mujoco.MjData(model)
    steps = 20000
    t0 = time.perf_counter()
    for _ in range(steps):
        mujoco.mj_step(model, data)
    raw = steps * model.opt.timestep / (time.perf_counter() - t0)
    return ours, raw, ours / raw, below[0] / wall


def motion_layer_ms(x_realtime: float, servo_share: float) -> float:
    """Wall time (ms) per simulated second above the servo (the motion layer's cycle, planning included), of a
    bench_speed run: the part of the wall time not spent in `layer.backend.advance`."""
    return 1000.0 / x_realtime * (1.0 - servo_share)


def servo_plant_ms(x_realtime: float, servo_share: float) -> float:
    """Wall time (ms) per simulated second in `layer.backend.advance` (the servo, the plant, mj_step) of a run."""
    return 1000.0 / x_realtime * servo_share


#: The constraint solvers a step of the elastic plant is timed with (`plant_step_us`): the printed suffix, then
#: (MuJoCo's solver, islands on, other options); "lean" is the plant's own choice, "none" no friction rows at all.
STEP_SOLVERS = {"": ("lean", False, {}), "_newton_friction_solver": ("mjSOL_NEWTON", True, {}),
                "_newton_one_iteration": ("mjSOL_NEWTON", True, {"iterations": 1}),
                "_newton_dense_jacobian": ("mjSOL_NEWTON", True, {"jacobian": 0}),
                "_newton_sparse_jacobian": ("mjSOL_NEWTON", True, {"jacobian": 1}),
                "_cg": ("mjSOL_CG", True, {}), "_pgs_with_islands": ("mjSOL_PGS", True, {}),
                "_without_friction_rows": ("none", False, {})}


def plant_step_us(robot: str, solver: tuple[str, bool, dict[str, int]], steps: int = 10000, repeats: int = 7) -> float:
    """Microseconds per mj_step of the elastic-gear plant alone (mujoco.rollout: no Python between the steps), its
    drives holding a 0.3 rad sine on every joint: the best of `repeats` (the least disturbed by the machine's
    load). `solver`: a value of STEP_SOLVERS."""
    import mujoco
    from mujoco import rollout

    name, islands, options = solver
    cell = realistic.RealisticCell(robot, elastic=True)
    cell.warm_up()
    model, data = cell._model, cell._data
    if name == "none":
        model.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_FRICTIONLOSS)
    elif name != "lean":
        model.opt.solver = getattr(mujoco.mjtSolver, name)
        if islands:
            model.opt.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_ISLAND)
        for option, value in options.items():
            setattr(model.opt, option, value)
    n = cell.n_joints
    cell.drives.set_drive_gains(np.full(n, 20000.0), np.full(n, 300.0), np.zeros(n), np.zeros(n))
    controls = np.zeros((1, steps, model.nu))
    t_s = np.arange(steps) * cell.timestep_s
    controls[0, :, 0 : 3 * n : 3] = np.asarray(cell.description.robot_spec.home_q_rad) + 0.3 * np.sin(2.0 * t_s)[:, None]
    state = np.empty(mujoco.mj_stateSize(model, mujoco.mjtState.mjSTATE_FULLPHYSICS))
    mujoco.mj_getState(model, data, state, mujoco.mjtState.mjSTATE_FULLPHYSICS)
    best_s = math.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        rollout.rollout(model, data, state, controls)
        best_s = min(best_s, time.perf_counter() - t0)
    return best_s / steps * 1e6


def naive_quintic_time(layer: MotionLayer, q0: np.ndarray, q1: np.ndarray) -> float:
    """Shortest duration of q0 + (q1-q0) * (10t^3 - 15t^4 + 6t^5) that keeps speed, acceleration and torque limits."""
    arm = layer.kin.arm
    d = np.abs(q1 - q0)
    t = max(float(np.max(1.875 * d / arm.qd_max)), math.sqrt(float(np.max(5.7735 * d / arm.qdd_max))))
    u = np.linspace(0.0, 1.0, 201)
    p1 = 30 * u**2 - 60 * u**3 + 30 * u**4
    p2 = 60 * u - 180 * u**2 + 120 * u**3
    p0 = 10 * u**3 - 15 * u**4 + 6 * u**5

    def torque_ok(T: float) -> bool:
        for a, b, c in zip(p0, p1, p2):
            tau = arm.inverse_dynamics(q0 + (q1 - q0) * a, (q1 - q0) * b / T, (q1 - q0) * c / T**2)
            if np.any(np.abs(tau) > arm.tau_max * TORQUE_SHARE):
                return False
        return True

    if torque_ok(t):
        return t
    lo, hi = t, 2 * t
    while not torque_ok(hi):
        lo, hi = hi, 2 * hi
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if torque_ok(mid) else (mid, hi)
    return hi


def bench_optimality(robot: str, plant: str = "realistic",
                     averaging: str = "default") -> tuple[float, float, float, float, float]:
    """Worst and mean executed/TOPP-RA-bound ratio; our time over the naive quintic: all joint moves, short, long."""
    layer = warm_realistic(robot, plant, averaging)
    ratios: list[float] = []
    ours: dict[str, list[float]] = {"short": [], "long": []}
    naive: dict[str, list[float]] = {"short": [], "long": []}
    moves = [(JointMotion(tuple(q)), "short") for q in joint_targets(layer)]
    moves += [(JointMotion(tuple(q)), "long") for q in long_joint_targets(layer)]
    moves += [(JointMotion(tuple(layer.kin.arm.home_q)), "")]  # back in front of the robot for the lines
    moves += [(CartesianMotion(p), "") for p in cart_targets(layer)]
    for motion, group in moves:
        q_start = layer.current_q()
        h = layer.move(motion, Params())
        traj = layer._traj
        path, limits = SplinePath(traj.path.dense), h.plan.limits
        layer.wait(h)
        executed = h.t_end_s - h.start_time_s  # reference time from start to the end of the path
        grid, sd = toppra_profile(path, limits, points=FINE_GRID_POINTS)
        bound = float(np.sum(segment_times(grid, sd)))
        ratios.append(executed / bound)
        if group:
            ours[group].append(executed)
            naive[group].append(naive_quintic_time(layer, q_start, np.array(motion.target_rad)))
    every = (sum(ours["short"]) + sum(ours["long"])) / (sum(naive["short"]) + sum(naive["long"]))
    return (max(ratios), float(np.mean(ratios)), every,
            sum(ours["short"]) / sum(naive["short"]), sum(ours["long"]) / sum(naive["long"]))


def bench_lmove_deviation(robot: str, plant: str = "realistic", averaging: str = "default") -> float:
    """Largest distance (mm) of the measured TCP from the programmed line, every servo step, LMOVEs at full speed
    (on elastic gears the TCP of the links' own angles: where the tool really is)."""
    layer = warm_realistic(robot, plant, averaging)
    loop = layer.backend.loop
    joints = (lambda: loop.cell.link_q) if plant == "elastic-gears" else (lambda: loop.cell.q)
    worst = 0.0
    line: list[np.ndarray] = []

    def measure() -> None:
        nonlocal worst
        if not line:
            return
        a, b = line
        p = layer.kin.fk(joints())[:3, 3]
        u = np.clip((p - a) @ (b - a) / ((b - a) @ (b - a)), 0.0, 1.0)
        worst = max(worst, float(np.linalg.norm(p - (a + u * (b - a)))))

    loop.on_step.append(measure)
    for target in cart_targets(layer):
        a = layer.tcp_pose()[:3, 3]
        h = layer.move(CartesianMotion(target), Params())
        line[:] = [a, target.matrix()[:3, 3]]
        layer.wait(h)
        line.clear()
    return worst * 1000.0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robot", default="irb2400")
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument("--only", choices=["elastic_state_feedback", "optimality"], default=None,
                    help="run only this variant's speed runs (median of five), or only the optimality figures")
    args = ap.parse_args()
    elastic = {"elastic": True, "gear_feedforward": True}
    if args.only == "optimality":
        print(f"robot={args.robot}")
        print_optimality(args.robot)
        return
    if args.only == "elastic_state_feedback":
        runs: dict[str, list[tuple[float, float, float, float]]] = {"": [], "_newton_friction_solver": []}
        for _ in range(5):   # alternately: the machine's load falls on both alike
            for suffix, lean in (("", True), ("_newton_friction_solver", False)):
                realistic.LEAN_FRICTION_SOLVER = lean
                runs[suffix].append(bench_speed(args.robot, args.seconds / 5, **elastic, state_feedback=True))
        realistic.LEAN_FRICTION_SOLVER = True
        print(f"robot={args.robot}")
        if has_elastic_gears(args.robot):
            steps_us: dict[str, list[float]] = {suffix: [] for suffix in STEP_SOLVERS}
            for _ in range(3):
                for suffix, us in steps_us.items():
                    us.append(plant_step_us(args.robot, STEP_SOLVERS[suffix]))
            for suffix, us in steps_us.items():
                print(f"elastic_plant_mj_step_us{suffix}={min(us):.2f}")
        for suffix, suffix_runs in runs.items():
            ours, raw, ratio, share = sorted(suffix_runs, key=lambda r: r[2])[2]
            print(f"raw_mujoco_x_realtime{suffix}={raw:.0f}")
            print(f"sim_vs_raw_mujoco_ratio_elastic_state_feedback{suffix}={ratio:.3f}")
            print(f"motion_layer_ms_per_sim_s_elastic_state_feedback{suffix}={motion_layer_ms(ours, share):.2f}")
            print(f"servo_plant_ms_per_sim_s_elastic_state_feedback{suffix}={servo_plant_ms(ours, share):.2f}")
        return
    # the machine is shared: the median of five runs of the stack, each against raw mj_step in the same run
    runs = sorted((bench_speed(args.robot, args.seconds / 5) for _ in range(5)), key=lambda r: r[2])
    ours, raw, ratio, servo_share = runs[2]
    python_law = sorted(bench_speed(args.robot, args.seconds / 5, compiled=False)[2] for _ in range(5))[2]
    numpy_bookkeeping = sorted(bench_speed(args.robot, args.seconds / 5, kernels=False)[2] for _ in range(5))[2]
    # the elastic gears (opt-in): the cascade with the twist fed forward, and the state feedback (slow joints)
    elastic_ff = sorted(bench_speed(args.robot, args.seconds / 5, **elastic)[2] for _ in range(5))[2]
    sf_runs = sorted((bench_speed(args.robot, args.seconds / 5, **elastic, state_feedback=True) for _ in range(5)),
                     key=lambda r: r[2])
    elastic_sf = sf_runs[2][2]
    # the state feedback's motion cycle as the Python loop (its law's kernels on), not the one kernel
    elastic_sf_loop = sorted(bench_speed(args.robot, args.seconds / 5, False, **elastic, state_feedback=True)[2]
                             for _ in range(5))[2]
    worst, mean, naive, naive_short, naive_long = bench_optimality(args.robot)
    dev = bench_lmove_deviation(args.robot)
    print(f"robot={args.robot}")
    print(f"raw_mujoco_x_realtime={raw:.0f}")
    print(f"time_optimality_mean={mean:.4f}")
    print(f"servo_plant_share_of_wall_time={servo_share:.3f}")
    print(f"vs_naive_ratio_short_moves={naive_short:.3f}")
    print(f"vs_naive_ratio_long_moves={naive_long:.3f}")
    print(f"sim_speed_x_realtime={ours:.1f}")
    print(f"compiled_kernels={AVAILABLE}")
    print(f"sim_vs_raw_mujoco_ratio_python_servo_law={python_law:.3f}")
    print(f"sim_vs_raw_mujoco_ratio_numpy_bookkeeping={numpy_bookkeeping:.3f}")
    print(f"sim_vs_raw_mujoco_ratio={ratio:.3f}")
    print(f"sim_vs_raw_mujoco_ratio_elastic_gear_feedforward={elastic_ff:.3f}")
    print(f"sim_vs_raw_mujoco_ratio_elastic_state_feedback={elastic_sf:.3f}")
    print(f"sim_vs_raw_mujoco_ratio_elastic_state_feedback_python_loop={elastic_sf_loop:.3f}")
    print(f"motion_layer_ms_per_sim_s={motion_layer_ms(ours, servo_share):.2f}")
    print(f"motion_layer_ms_per_sim_s_elastic_state_feedback={motion_layer_ms(sf_runs[2][0], sf_runs[2][3]):.2f}")
    print(f"servo_plant_ms_per_sim_s_elastic_state_feedback={servo_plant_ms(sf_runs[2][0], sf_runs[2][3]):.2f}")
    print(f"time_optimality_ratio={worst:.4f}")
    print(f"vs_naive_ratio={naive:.3f}")
    print(f"lmove_path_deviation_mm={dev:.3f}")
    if has_elastic_gears(args.robot):
        print_elastic_optimality(args.robot)


def print_optimality(robot: str) -> None:
    """The optimality figures alone: the rigid gears' and, for a robot that has them, the elastic gears'."""
    worst, mean, naive, naive_short, naive_long = bench_optimality(robot)
    print(f"time_optimality_mean={mean:.4f}")
    print(f"vs_naive_ratio_short_moves={naive_short:.3f}")
    print(f"vs_naive_ratio_long_moves={naive_long:.3f}")
    print(f"time_optimality_ratio={worst:.4f}")
    print(f"vs_naive_ratio={naive:.3f}")
    print(f"lmove_path_deviation_mm={bench_lmove_deviation(robot):.3f}")
    if has_elastic_gears(robot):
        print_elastic_optimality(robot)


def print_elastic_optimality(robot: str) -> None:
    """Time optimality, gain over naive and LMOVE deviation (at the links) on the elastic gears under their state
    feedback: with the layer's averaging of moves from rest (each over as much of the anti-resonance periods as its
    steps twist the gears) and, in the same run, with every move over the whole periods (`_whole_periods`,
    `scaled_averaging=False`) and without averaging (`_no_averaging`)."""
    for suffix, averaging in {"": "default", "_whole_periods": "whole", "_no_averaging": "none"}.items():
        worst, mean, naive, _, _ = bench_optimality(robot, "elastic-gears", averaging)
        dev = bench_lmove_deviation(robot, "elastic-gears", averaging)
        shown = warm_realistic(robot, "elastic-gears", averaging).smoothing_s
        print(f"elastic_smoothing_windows_s{suffix}={' '.join(f'{w:.3f}' for w in shown) or 'none'}")
        print(f"time_optimality_mean_elastic_state_feedback{suffix}={mean:.4f}")
        print(f"time_optimality_ratio_elastic_state_feedback{suffix}={worst:.4f}")
        print(f"vs_naive_ratio_elastic_state_feedback{suffix}={naive:.4f}")  # (at its target: the 4th decimal tells)
        print(f"lmove_path_deviation_mm_elastic_state_feedback{suffix}={dev:.3f}")

if __name__ == "__main__":
    main()
