"""The hardware room's grip watch: when a servo gripper has arrived, and whether it stopped on an object."""

from __future__ import annotations

#: A gripper servo has arrived within this many counts of its goal.
ARRIVED_COUNTS = 8
#: A servo stopped short of its goal with this share of its current cap (or more) is squeezing an object.
HOLDING_CURRENT_SHARE = 0.8


class GripWatch:
    """One gripper move: it has arrived when it is at its goal, or has moved and stopped (on a part)."""

    def __init__(self, goal_count: int, current_cap_a: float) -> None:
        self.goal_count = goal_count
        self.current_cap_a = current_cap_a
        self.seen_moving = False
        self.holding = False  #: stopped short of the goal, pushing at (nearly) its current cap: a grip

    def arrived(self, count: int, speed: int, current_a: float) -> bool:
        """Given what the servo reports now (whole counts, speed in its units, current in A)."""
        close = abs(count - self.goal_count) <= ARRIVED_COUNTS
        self.seen_moving = self.seen_moving or speed != 0
        stopped = self.seen_moving and speed == 0
        if stopped and not close:
            self.holding = current_a >= HOLDING_CURRENT_SHARE * self.current_cap_a
        return close or stopped
