"""The virtual arm on bus servos as a motion Backend: goal positions streamed to the servos' own loops, as on the bus."""

from __future__ import annotations

from typing import Any

import numpy as np

from orc_rpl.errors import UsageError
from orc_rpl.hardware.droop import SETTLED_COUNTS, DroopCorrection
from orc_rpl.hardware.grip import GripWatch
from orc_rpl.plant.servo_gripper import GripperServo, ServoGripper

SETTLE_RAD_S = 0.05  #: a FINE move has come to rest below this joint speed, as on the bus


class ServoArmBackend:
    """One goal per motion period to every servo (with the host's droop correction, hardware.droop), then the
    plant's 1 ms steps until the next (thesis 5.4).

    The servos' position loops are in the plant (`plant.servo_arm.ServoArmCell`): this backend is its
    own `loop` for the parts of orc_rpl that look for the cell there (IO, payload, pictures).
    """

    measures_torque = False  #: like the servos on the bus: load (duty) and current, not joint torque

    def __init__(self, cell: Any, motion_period_s: float) -> None:
        self.cell = cell
        self.loop = self
        self.servo_period_s = float(motion_period_s)
        self._steps = round(motion_period_s / cell.timestep_s)
        if self._steps < 1 or abs(self._steps * cell.timestep_s - motion_period_s) > 1e-9:
            raise UsageError(f"motion period {motion_period_s} s must be a whole number of plant steps ({cell.timestep_s} s)")
        self.settle_rad = SETTLED_COUNTS * cell.plant.rad_per_count
        self._droop = DroopCorrection(cell.n_joints, cell.plant.rad_per_count)
        self.settle_rad_s = SETTLE_RAD_S
        self._stall_nm = cell.plant.stall_torque_nm
        p = cell.plant
        # the gripper: the arm's next servo, its jaw driven as on the bus (current-capped), nothing to grip
        self.gripper_id = cell.n_joints + 1
        self.jaw = ServoGripper(GripperServo(p.stall_torque_nm, p.stall_current_a, p.no_load_speed_rad_s, p.rad_per_count))
        self._jaw_goal_rad, self._jaw_cap_a = self.jaw.angle_rad, 0.0
        self._grip: GripWatch | None = None

    def advance(self, q_ref: np.ndarray, qd_ref: np.ndarray, qdd_ref: np.ndarray) -> None:
        self.cell.set_goals(self._droop.goal(q_ref[-1], self.cell.q, self.cell.qd))
        dt, jaw = self.cell.timestep_s, self.jaw
        for _ in range(self._steps):
            self.cell.step_servos()
            if self._grip is not None:
                jaw.step(self._jaw_goal_rad, self._jaw_cap_a, dt)

    def q(self) -> np.ndarray:
        return self.cell.q

    def qd(self) -> np.ndarray:
        return self.cell.qd

    def torque(self) -> np.ndarray:
        """An estimate from the motors' duty (share of the stall torque), as on the bus: not a torque measurement."""
        return self.cell.duty * self._stall_nm

    def time_s(self) -> float:
        return self.cell.time_s

    def reset(self, q: np.ndarray) -> None:
        self.cell.reset(q)
        self._droop.clear()

    def hold(self) -> None:
        """Goal = where each servo is: they stop and hold (torque stays on)."""
        self.cell.set_goals(self.cell.q)

    # -- the gripper servo, as on the bus --------------------------------------------------------

    def drive_servo(self, servo_id: int, angle_rad: float, current_limit_a: float) -> None:
        """Send the gripper's servo to an angle with its current capped at current_limit_a."""
        if servo_id != self.gripper_id:
            raise UsageError(f"the simulated {self.cell.robot}'s gripper is servo {self.gripper_id}, not {servo_id}")
        self._jaw_goal_rad, self._jaw_cap_a = angle_rad, current_limit_a
        self._grip = GripWatch(self._count(angle_rad), current_limit_a)

    def servo_arrived(self, servo_id: int) -> bool:
        jaw = self.jaw
        speed = int(round(jaw.speed_rad_s / self.cell.plant.rad_per_count))  # whole counts per second
        return self._grip is None or self._grip.arrived(self._count(jaw.angle_rad), speed, jaw.current_a)

    def servo_holding(self, servo_id: int) -> bool:
        return self._grip is not None and self._grip.holding

    def _count(self, angle_rad: float) -> int:
        return int(round(angle_rad / self.cell.plant.rad_per_count))

    def describe(self) -> dict[str, Any]:
        """Figures for the run's summary, as the bus backend gives them."""
        p = self.cell.plant
        return {"servo": p.servo, "motion_period_ms": 1000.0 * self.servo_period_s,
                "temperature_c": [float(t) for t in self.cell.temperature_c]}
