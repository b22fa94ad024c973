"""Servo-bus benchmark: a motion cycle on the paced emulator against the wire, the motion rate, LMOVE path error.

Run: python benchmarks/bench_bus.py [--bus feetech|dynamixel] [--cycles 500]
Starts `orc bus emulate` (its own process), then prints `key=value` figures:
bus_cycle_ms (median of one SYNC WRITE of 6 goal positions and one SYNC READ of 6 state blocks),
bus_wire_ms (the time the same bytes take on a 1 Mbaud wire with the return delays configured: 0),
bus_cycle_vs_wire_ratio (target <= 1.3), the motion period the backend chose, and the largest
distance of the measured TCP from the line of a 200 mm LMOVE on the emulated arm, with the same
LMOVE on the simulated SO-101 (its realistic plant, which the emulator answers from, and the ideal
plant, the controller's own model) as the baselines of the same run.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time

import numpy as np

from orc_rpl.hardware.backend import BusBackend
from orc_rpl.hardware.bus import ServoBus
from orc_rpl.hardware.calibration import nominal
from orc_rpl.hardware.emulator import codec_for
from orc_rpl.hardware.packets import SYNC_READ, SYNC_WRITE, read_params, sync_write_params
from orc_rpl.motion import CartesianMotion, MotionLayer, Params, make_virtual_motion_layer
from orc_rpl.motion.kinematics import Kinematics
from orc_rpl.robot import ArmModel, solve_ik
from orc_rpl.robot.robots import ROBOTS
from orc_rpl.world.pose import Pose

BAUD = 1_000_000
IDS = [1, 2, 3, 4, 5, 6]
START = Pose(0.200, -0.100, 0.030, 0.0, np.pi, 0.0)
END = Pose(0.200, 0.100, 0.030, 0.0, np.pi, 0.0)
SPEED_M_S = 0.1


def wire_ms(bus: ServoBus, goal_size: int, block: tuple[int, int]) -> float:
    """The bytes of one cycle on the wire: the sync write, the sync read request and each reply (return delay 0)."""
    codec = bus.codec
    write = codec.instruction(codec.broadcast_id, SYNC_WRITE,
                              sync_write_params(codec, 42, goal_size, {i: bytes(goal_size) for i in IDS}))
    request = codec.instruction(codec.broadcast_id, SYNC_READ, read_params(codec, *block) + bytes(IDS))
    replies = sum(len(codec.status(i, 0, bytes(block[1]))) for i in IDS)
    return 1000.0 * bus.wire_s(len(write) + len(request) + replies)


def bus_cycles(bus: ServoBus, backend: BusBackend, cycles: int) -> np.ndarray:
    """Milliseconds of each whole cycle: all six servos (the gripper too) told to stay where they are, then read."""
    model = backend.model
    goal = model.reg("goal_position")
    goals = {i: goal.encode(model.value("present_position", bus.read(i, *model.state_block))) for i in IDS}
    times = []
    for _ in range(cycles):
        start = time.perf_counter()
        bus.sync_write(goal.address, goal.size, goals)
        bus.sync_read(*model.state_block, IDS)
        times.append(time.perf_counter() - start)
    return 1000.0 * np.array(times)


def lmove_error_mm(layer: MotionLayer, measured_q) -> float:
    """Largest distance (mm) of the measured TCP from the straight line of a 200 mm LMOVE, every motion cycle."""
    layer.wait(layer.move(CartesianMotion(START, kind="joint"), Params()))
    layer.run_for(0.5)
    a, b = START.matrix()[:3, 3], END.matrix()[:3, 3]
    handle = layer.move(CartesianMotion(END), Params(speed_m_s=SPEED_M_S))
    worst = 0.0
    while not handle.done:
        layer.tick()
        p = layer.kin.fk(measured_q())[:3, 3]
        u = np.clip((p - a) @ (b - a) / ((b - a) @ (b - a)), 0.0, 1.0)
        worst = max(worst, float(np.linalg.norm(p - (a + u * (b - a)))))
    return 1000.0 * worst


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bus", choices=("feetech", "dynamixel"), default="feetech")
    ap.add_argument("--cycles", type=int, default=500)
    args = ap.parse_args()
    emulator = subprocess.Popen([sys.executable, "-m", "orc_rpl", "bus", "emulate", "--robot", "so101", "--bus", args.bus,
                                 "--baud", str(BAUD)], stdout=subprocess.PIPE, text=True)
    try:
        port = emulator.stdout.readline().strip()
        spec = ROBOTS.get("so101")
        bus = ServoBus(port, codec_for(args.bus), BAUD)
        backend = BusBackend(bus, nominal(spec, args.bus))
        cycle = bus_cycles(bus, backend, args.cycles)
        wire = wire_ms(bus, backend.model.reg("goal_position").size, backend.model.state_block)
        layer = MotionLayer(Kinematics(ArmModel(spec), solve_ik), backend, backend.servo_period_s)
        on_bus = lmove_error_mm(layer, backend.q)
        backend.hold()
        sim = make_virtual_motion_layer("so101", motion_period_s=backend.servo_period_s)  # the realistic plant
        on_sim = lmove_error_mm(sim, sim.backend.q)
        ideal = make_virtual_motion_layer("so101", motion_period_s=backend.servo_period_s, plant="ideal")
        on_ideal = lmove_error_mm(ideal, ideal.backend.q)
    finally:
        emulator.terminate()
        emulator.wait()
    print(f"bus={args.bus}")
    print(f"servos={len(IDS)}")
    print(f"baud={BAUD}")
    print(f"bus_cycle_p90_ms={np.percentile(cycle, 90):.3f}")
    print(f"motion_period_ms={1000 * backend.servo_period_s:.0f}")
    print(f"motion_rate_hz={1.0 / backend.servo_period_s:.0f}")
    print(f"lmove_200mm_speed_mm_s={1000 * SPEED_M_S:.0f}")
    print(f"lmove_200mm_path_error_ideal_mm={on_ideal:.3f}")
    print(f"lmove_200mm_path_error_sim_mm={on_sim:.3f}")
    print(f"lmove_200mm_path_error_mm={on_bus:.3f}")
    print(f"bus_wire_ms={wire:.3f}")
    print(f"bus_cycle_ms={np.median(cycle):.3f}")
    print(f"bus_cycle_vs_wire_ratio={np.median(cycle) / wire:.3f}")


if __name__ == "__main__":
    main()
