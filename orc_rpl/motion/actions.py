"""Actions (thesis 4.4): callables run inside the motion cycle with a read-only view of the motion, a result slot and the move's semaphore."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from orc_rpl.errors import UsageError

STAGES = ("pre", "during", "post", "continuous")


class MoveSignal:
    """The semaphore of a move (`MoveSignal`): actions and the layer signal it, the caller waits on it."""

    def __init__(self) -> None:
        self.count = 0
        #: every signal as (who signalled, controller time in s), in order
        self.events: list[tuple[str, float]] = []

    def signal(self, reason: str, time_s: float) -> None:
        """V operation: one more pending signal."""
        self.count += 1
        self.events.append((reason, time_s))

    def take(self) -> bool:
        """P operation without blocking: consume one pending signal if there is one."""
        if self.count > 0:
            self.count -= 1
            return True
        return False

    @property
    def last_reason(self) -> str | None:
        """Who signalled last ("done" when the layer did at the end of the move)."""
        return self.events[-1][0] if self.events else None


@dataclass(frozen=True, slots=True)
class MotionData:
    """What an action sees in one motion cycle (read-only: arrays are not writeable)."""

    time_s: float                 #: controller time
    t_motion_s: float             #: time since this move started
    s: float                      #: this move's path coordinate in [0, 1]
    q: np.ndarray                 #: measured joint positions, rad
    qd: np.ndarray                #: measured joint velocities, rad/s
    q_ref: np.ndarray             #: commanded joint positions
    qd_ref: np.ndarray            #: commanded joint velocities
    torque: np.ndarray            #: joint torques (measured or estimated), N m
    position_error: np.ndarray    #: q_ref - q, rad
    t_end_s: float                #: T_d: controller time when the move is expected to end
    stage: str                    #: "pre", "during", "post" or "continuous"
    sensors: dict[str, Any] = field(default_factory=dict)  #: installed sensors' values (later issues)

    @property
    def T_d(self) -> float:  # noqa: N802 - the thesis' name
        """The expected end time of the motion (thesis notation)."""
        return self.t_end_s


class ActionSlot:
    """An action's own result slot, and its only ways to affect the move: signal, record, request a stop."""

    def __init__(self, name: str, signal: MoveSignal) -> None:
        self.name = name
        self.value: Any = None
        self.records: list[Any] = []
        self.signalled_at_s: float | None = None
        self.stop_requested = False
        self._signal = signal
        self._now_s = 0.0

    def signal(self, value: Any = None) -> None:
        """Store `value` (if given) and signal the move's semaphore with this action's name."""
        if value is not None:
            self.value = value
        if self.signalled_at_s is None:
            self.signalled_at_s = self._now_s
        self._signal.signal(self.name, self._now_s)

    def record(self, item: Any) -> None:
        """Append to this action's recording."""
        self.records.append(item)

    def request_stop(self) -> None:
        """Ask the layer to stop the move on its path at the end of this cycle (an UNTIL condition)."""
        self.stop_requested = True


Action = Callable[[MotionData, ActionSlot], None]


@dataclass(slots=True)
class _Entry:
    stage: str
    name: str
    fn: Action
    slot: ActionSlot


class Actions:
    """The action set of one move (`ActionSet`): pre, during, post and continuous actions, in the order given."""

    def __init__(
        self,
        pre: Iterable[Action] = (),
        during: Iterable[Action] = (),
        post: Iterable[Action] = (),
        continuous: Iterable[Action] = (),
    ) -> None:
        self.signal = MoveSignal()
        self._entries: list[_Entry] = []
        for stage, fns in zip(STAGES, (pre, during, post, continuous)):
            for fn in fns:
                self.add(stage, fn)

    def add(self, stage: str, fn: Action, name: str | None = None) -> ActionSlot:
        """Add an action; its name (default: the function's) keys its result slot."""
        if stage not in STAGES:
            raise UsageError(f"action stage must be one of {', '.join(STAGES)}, not {stage!r}")
        if name is None:
            # Unnamed actions (several lambdas) share their function's name: number them `<lambda>_2`, ...
            base = getattr(fn, "__name__", "action")
            taken = {e.name for e in self._entries}
            name = next(f"{base}_{k}" if k > 1 else base for k in range(1, len(taken) + 2)
                        if (f"{base}_{k}" if k > 1 else base) not in taken)
        if any(e.name == name for e in self._entries):
            raise UsageError(f"an action named {name!r} is already in this action set")
        entry = _Entry(stage, name, fn, ActionSlot(name, self.signal))
        self._entries.append(entry)
        return entry.slot

    def stage(self, stage: str) -> list[_Entry]:
        """The entries of one stage, in order."""
        return [e for e in self._entries if e.stage == stage]

    def slot(self, name: str) -> ActionSlot:
        """The result slot of an action."""
        for e in self._entries:
            if e.name == name:
                return e.slot
        raise UsageError(f"no action named {name!r}; actions: {', '.join(e.name for e in self._entries)}")

    def result(self, name: str) -> Any:
        """The value an action left in its slot (`GetResult`)."""
        return self.slot(name).value

    def run(self, stage: str, data: MotionData) -> bool:
        """Run one stage's actions in order; True if any asked for a stop."""
        stop = False
        for e in self._entries:
            if e.stage == stage:
                e.slot._now_s = data.time_s
                e.fn(data, e.slot)
                stop = stop or e.slot.stop_requested
        return stop

    def __bool__(self) -> bool:
        return bool(self._entries)


def until(condition: Callable[[MotionData], bool], name: str = "until") -> Actions:
    """An action set for `UNTIL condition`: when the condition holds, signal and stop on the path."""

    def check(data: MotionData, slot: ActionSlot) -> None:
        if not slot.stop_requested and condition(data):
            slot.signal(data.s)
            slot.request_stop()

    acts = Actions()
    acts.add("during", check, name)
    return acts
