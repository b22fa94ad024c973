"""The caller's handle on one move: its status, progress, expected end time and semaphore."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from orc_rpl.errors import OrcError
from orc_rpl.motion.actions import Actions, MoveSignal
from orc_rpl.motion.specs import Motion, MoveStatus, Params

if TYPE_CHECKING:
    from orc_rpl.motion.planner import Plan


@dataclass(eq=False, slots=True)
class MoveHandle:
    """One move as the caller sees it; the layer updates it every motion cycle."""

    id: int                                  #: unique per layer, in the order moves were requested
    motion: Motion
    params: Params
    actions: Actions                         #: the move's actions (an empty set when none were given)
    status: MoveStatus = MoveStatus.SPAWNED  #: ready/act_stopped/fault once done; spawned while it runs or waits
    short: bool = False                      #: a ShortMove (ruckig) rather than a Move
    started: bool = False                    #: the robot has begun this move
    done: bool = False                       #: finished (at rest within tolerance for FINE), stopped or refused
    s: float = 0.0                           #: path coordinate reached, 0..1
    start_time_s: float | None = None        #: controller time at the start
    end_time_s: float | None = None          #: controller time at the end (FINE: when settled)
    t_end_s: float | None = None             #: T_d: when the reference is expected to reach the end
    stopped_s: float | None = None           #: where a stop left the move (act_stopped)
    stopped_by: str | None = None            #: "stop_move", an action's name, or "cancelled" for a queued move
    settled: bool = True                     #: False if a FINE move's settling timed out
    blended: bool = False                    #: the move was joined to the next one through a zone
    replanned_during: bool = False           #: computation=done found no matching saved plan
    error: OrcError | None = None            #: what went wrong when status is fault
    plan: Plan | None = field(default=None, repr=False)
    pieces_left: list = field(default_factory=list, repr=False)

    @property
    def signal(self) -> MoveSignal:
        """The move's semaphore (`Act->MoveSignal`): signalled by actions and by the layer when done."""
        return self.actions.signal

    @property
    def zone_m(self) -> float:
        return self.params.zone_m

    def __repr__(self) -> str:
        return f"MoveHandle(id={self.id}, {type(self.motion).__name__}, status={self.status.value}, done={self.done}, s={self.s:.3f})"
