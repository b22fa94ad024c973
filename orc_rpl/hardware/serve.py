"""The hardware room's emulator process: a pseudo-terminal whose other end is an emulated arm on a servo bus."""

from __future__ import annotations

import os
import select
import sys
import time
import tty
from collections import deque
from typing import TextIO

from orc_rpl.hardware.emulated_arm import EmulatedArm
from orc_rpl.hardware.emulator import EmulatedBus, FaultPlan, hand_pose
from orc_rpl.hardware.packets import Instruction
from orc_rpl.robot.robots import ROBOTS

#: Physics steps between two looks at the wire, at most (the wire comes first).
MAX_CATCH_UP_STEPS = 20
#: The physics catches up with the wall clock from at most this far behind; beyond it (a starved process on a
#: busy machine) it stays behind, running slower than real time, rather than spend its time catching up.
MAX_LAG_S = 0.050


def open_pty() -> tuple[int, int, str]:
    """(master fd, slave fd, slave path) of a raw pseudo-terminal."""
    master, slave = os.openpty()
    tty.setraw(slave)
    return master, slave, os.ttyname(slave)


def serve(robot: str, bus: str, baud: int = 1_000_000, faults: tuple[FaultPlan, ...] = (), hand: bool = False,
          out: TextIO = sys.stdout, duration_s: float | None = None, object_rad: float | None = None) -> None:
    """Run the emulated arm until killed (or for duration_s); prints the port path first."""
    spec = ROBOTS.get(robot)
    n = len(spec.q_min_rad)
    emulated = EmulatedBus(bus, list(range(1, n + 2)), baud, faults)  # the arm's joints and the gripper
    arm = EmulatedArm(robot, emulated.servos, object_rad)
    master, slave, path = open_pty()
    out.write(f"{path}\n")
    out.write(f"emulating {robot} on a {bus} bus at {baud} baud: servo ids 1..{n} (joints), {n + 1} (gripper)\n")
    out.flush()
    codec = emulated.codec
    buffer = bytearray()
    outgoing: deque[tuple[float, bytes]] = deque()
    start = time.perf_counter()
    limp_since: float | None = None
    step_s = arm.cell.timestep_s
    lag_s = 0.0  #: how far the physics has fallen behind the wall clock on a busy machine, for good
    try:
        while duration_s is None or time.perf_counter() - start < duration_s:
            now = time.perf_counter() - start
            while outgoing and outgoing[0][0] <= now:
                os.write(master, outgoing.popleft()[1])
            if not select.select([master], [], [], 0)[0]:
                # only when every byte the host sent has been read: a stalled emulator must not take the host for silent
                emulated.watchdog(now)
            if now - lag_s - arm.time_s > MAX_LAG_S:
                lag_s = now - arm.time_s - MAX_LAG_S  # a starved emulator falls behind the wall clock, never races it
            steps = 0
            while arm.time_s + step_s <= now - lag_s and steps < MAX_CATCH_UP_STEPS:
                if hand:
                    # the hand takes the arm when the host switches the torque off (not while nobody has talked)
                    if emulated.torque_written:
                        emulated.torque_written = False
                        limp_since = now if not any(s.torque_on for s in arm.arm_servos) else None
                    arm.hand = None if limp_since is None else hand_pose(list(spec.q_min_rad), list(spec.q_max_rad), now - limp_since)
                arm.step()
                steps += 1
                if outgoing and outgoing[0][0] <= time.perf_counter() - start:
                    break  # a reply is due: the wire comes first
            due = [arm.time_s + step_s + lag_s]
            if outgoing:
                due.append(outgoing[0][0])
            wait = max(0.0, min(due) - (time.perf_counter() - start))
            if not select.select([master], [], [], wait)[0]:
                continue
            try:
                buffer += os.read(master, 4096)
            except OSError:  # no client has the port open just now
                time.sleep(0.01)
                continue
            received = time.perf_counter() - start
            while True:
                packet, used, complaint = codec.parse(buffer, host=True)
                if used:
                    del buffer[:used]
                if complaint is not None:
                    emulated.bad_packets += 1
                if isinstance(packet, Instruction):
                    arm.publish()  # the registers as the servos measure now
                    outgoing.extend(emulated.handle(packet, used, received))
                elif not used:
                    break
    finally:
        os.close(master)
        os.close(slave)
