"""The deburring room's compliant flange: the admittance loop on its stroke, and the watch both force loops keep.

GRINDMOVE (deburring_behaviour) drives this loop where a Grinder is installed with a force flange (FORCE_IN and
STROKE), and the arm's own loop (deburring_arm) otherwise; both keep a ForceWatch that stops an oscillating loop.
"""

from __future__ import annotations

import dataclasses
import math
from collections import deque
from collections.abc import Callable, Iterator
from typing import Any

from orc_rpl.application.runtime import MotionRequest
from orc_rpl.world.pose import Pose

#: The compliant flange's wiring: its force sensor and its stroke command.
FORCE_IN = 8
STROKE_OUT = 8
#: Admittance gain K (m of stroke per N of force error and second) and the stroke's range (m).
ADMITTANCE_M_PER_N_S = 2.5e-3
STROKE_LIMIT_M = 0.01
#: The force loop is unstable when, over this many cycles in contact, its error's RMS exceeds UNSTABLE_FRACTION
#: of the command and changes sign at least UNSTABLE_SIGN_CHANGES times (a stable loop's error on a bulge's
#: flank stays below a fifth of the command and keeps its sign).
UNSTABLE_WINDOW = 25
UNSTABLE_FRACTION = 0.5
UNSTABLE_SIGN_CHANGES = 8


class ForceWatch:
    """The force loop watching itself: its last UNSTABLE_WINDOW errors from the first contact on."""

    def __init__(self, dt_s: float, stiffness_limit_n_m: float, fraction: float = UNSTABLE_FRACTION) -> None:
        self.dt_s, self.stiffness_limit_n_m, self.fraction = dt_s, stiffness_limit_n_m, fraction
        self._errors: deque[float] = deque(maxlen=UNSTABLE_WINDOW)
        self._command = 0.0

    def observe(self, command: float, measured: float) -> None:
        if measured > 0.0 or self._errors:  # watched from the first contact on
            self._errors.append(command - measured)
        self._command = command

    def unstable(self) -> str | None:
        """Why the loop is oscillating (its error's RMS and sign changes over the window), or None."""
        errors = self._errors
        if len(errors) < UNSTABLE_WINDOW:
            return None
        rms = math.sqrt(sum(e * e for e in errors) / len(errors))
        changes = sum(1 for a, b in zip(errors, list(errors)[1:]) if a * b < 0)
        if rms > self.fraction * max(self._command, 1.0) and changes >= UNSTABLE_SIGN_CHANGES:
            return (f"the force loop is unstable: its error oscillates at {rms:.1f} N RMS about the commanded "
                    f"{self._command:.1f} N ({changes} sign changes in {1000 * UNSTABLE_WINDOW * self.dt_s:.0f} ms); "
                    f"the contact is stiffer than its gain allows (stable below "
                    f"{self.stiffness_limit_n_m / 1000:.0f} N/mm)")
        return None


class ForceLoop:
    """The admittance law on the flange's stroke, one step a motion cycle. GRINDMOVE drives it and the arm's own
    loop (deburring_arm.ArmForceLoop) through the same methods; the flange stays on the edge between moves."""

    #: The contact has settled the first cycle the force is within SETTLED_FRACTION of the command.
    settle_cycles = 1
    #: A pass over a bulge starts where the robot stopped (no lifting off: the stroke keeps the force).
    stays_on_edge = True

    def __init__(self, robot: Any, force: Callable[[float], float], force_in: int = FORCE_IN,
                 stroke_out: int = STROKE_OUT) -> None:
        self.robot, self.force = robot, force
        self.force_in, self.stroke_out = force_in, stroke_out
        self.stroke_m = 0.0
        self.touched = False  #: the sensor has read a contact force
        self._in, self._out = robot.io.bank("AnaIn"), robot.io.bank("AnaOut")
        self.watch = ForceWatch(robot.dt_s, 2 / (ADMITTANCE_M_PER_N_S * robot.dt_s))

    def measured_n(self) -> float:
        return float(self._in[self.force_in])

    def tip_offset_m(self) -> float:
        """How far the grinding tip sits from the TCP along -n: the flange's stroke."""
        return self.stroke_m

    def unstable(self) -> str | None:
        return self.watch.unstable()

    def step(self, s: float, arc_m: float = 0.0) -> tuple[float, float]:
        """Read the force, move the stroke; (commanded, measured) force."""
        command, measured = self.force(s), self.measured_n()
        self.touched = self.touched or measured > 0.0
        self.watch.observe(command, measured)
        self.stroke_m = min(STROKE_LIMIT_M, max(-STROKE_LIMIT_M, self.stroke_m + ADMITTANCE_M_PER_N_S * self.robot.dt_s
                                                * (command - measured)))
        self._out[self.stroke_out] = self.stroke_m
        return command, measured

    def retract(self) -> None:
        self.stroke_m = 0.0
        self._out[self.stroke_out] = 0.0

    def approach(self, start: Pose) -> Pose:
        """Where the move to the path's start goes: onto it."""
        return start

    def pressed_move(self, base: MotionRequest, start_m: float, end_m: float, target: Pose,
                     via: tuple[Pose, ...]) -> Iterator[Any]:
        """A grinding move from where the robot is to `target`; its ticket."""
        return (yield dataclasses.replace(base, target=target, via=via))

    def leave(self, base: MotionRequest, end: Pose) -> Iterator[Any]:
        """The path is done: the stroke back to 0."""
        self.retract()
        yield from ()

    def nothing_ground(self, settled: bool) -> str | None:
        """Why nothing was ground (the sensor never read a contact force), or None."""
        if self.touched:
            return None
        return (f"no contact force on AnalogIn[{self.force_in}] along the whole path: nothing was ground "
                "(no casting in the cell, or the path is not on its edge)")
