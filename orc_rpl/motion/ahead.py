"""Planning ahead (thesis 5.2, computation `save`/`done`): the next move planned on a worker thread while the cycle runs.

The worker has its own planner over its own arm model (an arm model holds state: the payload, the dynamics
buffers), so nothing it computes touches what the motion cycle uses. The plan it makes is the plan `save` would
store: the dense path and its first piece timed from rest. When the cycle keeps wall-clock time it never waits for
it: the caller asks `ready()` between cycles and submits the move once it is. In simulated time the clock stands
still while the plan is made, so runs stay deterministic; there the plan is made at once on the calling thread, with
the same planner: the executive asks for the move a statement later, before the cycle has run any of the move before,
so a worker thread would have the cycle wait for it anyway (bench_view: every plan taken was waited for, for as long
as the worker computed), and each hand-over to and from a thread costs a wake-up that another busy program on the
machine (a browser drawing the view) can delay by a scheduler slice.
"""

from __future__ import annotations

import os
import sys
import threading
import time
from collections.abc import Callable
import concurrent.futures
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np

from orc_rpl.errors import OrcError
from orc_rpl.motion import scheduling
from orc_rpl.motion.planner import Plan, Planner
from orc_rpl.motion.specs import Known, Motion, Params

#: While a plan is made on the worker, the interpreter hands the lock between threads this often (s): the motion
#: cycle, waking from its sleep, waits at most this long for the worker's Python code (the default is 5 ms).
SWITCH_INTERVAL_S = 0.0005

#: How much lower the worker's priority is than the motion cycle's (a nice value).
WORKER_NICE = 10

#: Motions the program knows well enough to plan before they are reached (thesis: completely and almost known).
PLANNED_AHEAD = (Known.COMPLETELY, Known.ALMOST)


def _lower_priority() -> None:
    """The worker thread yields the processor to the motion cycle (Linux schedules threads one by one)."""
    try:
        os.setpriority(os.PRIO_PROCESS, threading.get_native_id(), WORKER_NICE)
    except (AttributeError, OSError):  # not Linux, or not allowed: the worker runs at the cycle's priority
        pass


@dataclass
class Counts:
    """What planning ahead achieved in a run (reported by `orc run`)."""

    planned_ahead: int = 0      #: moves planned on the worker before they were submitted
    reused: int = 0             #: of those, plans used as made (start and target proved right)
    replanned: int = 0          #: plans thrown away: the move was not the one predicted, or started elsewhere
    at_start: int = 0           #: moves planned when submitted (partly and not known motions, first motions)
    from_dummy: int = 0         #: of those planned ahead, computed from sensor dummies (before the sensor answered)
    confirmed: int = 0          #: of those, the real sensor's answer gave the same motion
    corrected: int = 0          #: of those, the real answer moved the target a little: the plan used, corrected
    waited: int = 0             #: plans taken before the worker had made them: the motion cycle waited (simulated time)
    waited_s: float = 0.0       #: wall-clock seconds the motion cycle waited for the worker in those
    notes: list[str] = field(default_factory=list)


@dataclass
class _Job:
    motion: Motion
    params: Params
    start_q: np.ndarray
    future: Future[Plan | None]


class PlanAhead:
    """One worker thread and the plans it made, by descriptor."""

    def __init__(self, make_planner: Callable[[], Planner], paced: bool) -> None:
        self._make_planner = make_planner
        #: the motion cycle keeps wall-clock time (--realtime, hardware): it goes on while a plan is made. In simulated
        #: time the clock stands while the worker plans, so a run is the same whatever the machine's load
        self.paced = paced
        #: plans are made on the worker thread (in simulated time they are made at once on the calling thread: see
        #: the module's docstring; bench_view sets it to measure the difference)
        self.on_worker = paced
        self._planner: Planner | None = None
        self._pool: ThreadPoolExecutor | None = None
        self._jobs: dict[int, _Job] = {}
        self._next = 1
        self._lock = threading.Lock()
        self._previous_interval: float | None = None
        self.counts = Counts()

    def _work(self, motion: Motion, params: Params, start_q: np.ndarray, cap: float | None,
              reserve: np.ndarray | float) -> Plan | None:
        if self._planner is None:
            self._planner = self._make_planner()
            if self.on_worker:
                _lower_priority()
        if self.on_worker:
            scheduling.follow_paced()  # a paced cycle at real-time priority must not wait on a preempted worker's lock
        planner = self._planner
        planner.tcp_speed_cap_m_s, planner.friction_reserve_nm = cap, reserve
        plan = planner.plan(0, motion, params, start_q)
        if plan is not None and plan.timed is None:
            plan.saved_first = planner.time(plan.pieces[0], plan.limits, 0.0, params.time_s if len(plan.pieces) == 1 else None,
                                             params.whole_averaging)
        return plan

    def start(self, motion: Motion, params: Params, start_q: np.ndarray, main: Planner) -> int:
        """Plan `motion` from `start_q` on the worker (in simulated time: now, on this thread); returns the descriptor
        to submit it with (computation done)."""
        start_q = np.array(start_q, dtype=float)
        future: Future[Plan | None] = Future()
        if self.on_worker:
            future = self._submit(motion, params, start_q, main)
        else:
            try:
                future.set_result(self._work(motion, params, start_q, main.tcp_speed_cap_m_s, main.friction_reserve_nm))
            except Exception as error:  # as the worker's future would hold it: take() raises it where it is submitted
                future.set_exception(error)
        descriptor = self._next
        self._next += 1
        self._jobs[descriptor] = _Job(motion, params, start_q, future)
        self.counts.planned_ahead += 1
        return descriptor

    def _submit(self, motion: Motion, params: Params, start_q: np.ndarray, main: Planner) -> Future[Plan | None]:
        if self._pool is None:
            self._pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="orc-plan-ahead")
        with self._lock:
            if not self._jobs and self._previous_interval is None:
                self._previous_interval = sys.getswitchinterval()
                sys.setswitchinterval(min(self._previous_interval, SWITCH_INTERVAL_S))
        future = self._pool.submit(self._work, motion, params, start_q, main.tcp_speed_cap_m_s, main.friction_reserve_nm)
        future.add_done_callback(lambda _: self._restore_interval())
        return future

    def _restore_interval(self) -> None:
        with self._lock:
            if self._previous_interval is not None and all(j.future.done() for j in self._jobs.values()):
                sys.setswitchinterval(self._previous_interval)
                self._previous_interval = None

    def ready(self, descriptor: int) -> bool:
        job = self._jobs.get(descriptor)
        return job is None or not self.paced or job.future.done()

    def take(self, descriptor: int, motion: Motion, start_q: np.ndarray, main: Planner) -> Plan | None:
        """The plan made for `descriptor` if it is for this motion from this start (the program's knowledge
        proved right), with the motion cycle's own limits; None: plan now (`during`)."""
        job = self._jobs.pop(descriptor, None)
        if job is None:
            return None
        if not job.future.done():  # in simulated time the cycle waits for the worker here (ready() says True)
            self.counts.waited += 1
            start = time.perf_counter()
            concurrent.futures.wait([job.future])
            self.counts.waited_s += time.perf_counter() - start
        try:
            plan = job.future.result()  # at once when the caller waited for ready()
        except OrcError as error:  # it will fail again, where the program can be told: plan now
            self.counts.notes.append(str(error))
            plan = None
        if plan is None or job.motion != motion or not np.allclose(job.start_q, start_q, atol=1e-9, rtol=0.0):
            self.counts.replanned += 1
            return None
        self.counts.reused += 1
        plan.limits = main.limits(plan.params, plan.tool)  # the worker's limits call the worker's arm model
        return plan

    def forget(self) -> None:
        """Drop every plan not taken (a stop or a reset: they start where the robot no longer will be)."""
        self.counts.replanned += len(self._jobs)
        self._jobs.clear()

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True)
            self._pool = None
