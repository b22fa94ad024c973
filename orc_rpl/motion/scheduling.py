"""The motion cycle's place in the operating system's scheduler: a cycle paced to the wall clock runs at real-time priority."""

from __future__ import annotations

import ctypes
import os
import platform
import resource
import signal
import sys
import threading
import time
from typing import Any

#: The time slice a paced motion thread asks Linux for. Linux's EEVDF scheduler (6.12 and later) lets a waking
#: thread whose slice is shorter preempt the one running; with the default slice a paced cycle that woke while
#: another program (a browser drawing the 3D view in software) held the core waited for that program's slice to end.
#: bench_view measures it (`lateness_p99_ms` against `..._default_slice`).
PACED_SLICE_S: float | None = 100e-6

#: sched_setattr's system call number where Python has no wrapper for it.
_SCHED_SETATTR = {"x86_64": 314, "aarch64": 274}


class _SchedAttr(ctypes.Structure):
    """Linux's struct sched_attr (uapi/linux/sched/types.h)."""

    _fields_ = [("size", ctypes.c_uint32), ("sched_policy", ctypes.c_uint32), ("sched_flags", ctypes.c_uint64),
                ("sched_nice", ctypes.c_int32), ("sched_priority", ctypes.c_uint32),
                ("sched_runtime", ctypes.c_uint64), ("sched_deadline", ctypes.c_uint64),
                ("sched_period", ctypes.c_uint64), ("sched_util_min", ctypes.c_uint32),
                ("sched_util_max", ctypes.c_uint32)]


def request_slice(slice_s: float | None) -> bool:
    """Ask the scheduler to run the calling thread in slices of `slice_s` (None: the system's default slice), keeping
    its ordinary policy and nice value: no privilege needed. False where the system has no such request (then
    nothing changed)."""
    number = _SCHED_SETATTR.get(platform.machine())
    if not sys.platform.startswith("linux") or number is None or os.sched_getscheduler(0) != os.SCHED_OTHER:
        return False  # a thread someone made real-time (chrt) keeps its policy
    attr = _SchedAttr(size=ctypes.sizeof(_SchedAttr), sched_policy=os.SCHED_OTHER,
                      sched_nice=os.getpriority(os.PRIO_PROCESS, 0),
                      sched_runtime=0 if slice_s is None else int(slice_s * 1e9))
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        return libc.syscall(number, 0, ctypes.byref(attr), 0) == 0
    except (OSError, AttributeError):
        return False


#: The real-time priority (SCHED_FIFO, 1 to 99) a paced motion cycle asks for: above every ordinary program (a
#: browser drawing the view in software takes both cores otherwise), below the kernel's interrupt threads (50).
PACED_PRIORITY = 10

#: CPU time a real-time thread may spend without waiting before the kernel warns it (RLIMIT_RTTIME, s): a paced
#: motion cycle sleeps every cycle, so only a runaway (an endless loop without motions) or a very long plan made in
#: the cycle reaches it, and is then put back to normal priority instead of keeping a core from every other program.
RUNAWAY_CPU_S = 1.0


#: The paced block in force (PacedPriority), for the threads that follow it (follow_paced).
_paced: PacedPriority | None = None


class PacedPriority:
    """`with PacedPriority() as priority:` runs the calling thread at real-time priority (SCHED_FIFO) until the block
    ends, where it gets its policy back.

    Safe by construction: threads and processes it starts run at normal priority (SCHED_RESET_ON_FORK: an earlier try
    without it forked busy test processes that inherited the real-time policy and starved the run); a thread that
    computes RUNAWAY_CPU_S without waiting is put back to normal priority by the kernel's SIGXCPU (RLIMIT_RTTIME).
    Where it is not permitted (an ordinary user without CAP_SYS_NICE or an RLIMIT_RTPRIO) or not possible (not Linux,
    not the main thread), nothing changes and `refused` says why; `demoted` is true when the runaway guard fired.
    """

    def __init__(self, priority: int = PACED_PRIORITY, runaway_cpu_s: float = RUNAWAY_CPU_S) -> None:
        self.priority, self.runaway_cpu_s = priority, runaway_cpu_s
        self.refused: str | None = None
        self.demoted = False
        self._saved: tuple[int, os.sched_param, Any, tuple[int, int]] | None = None
        self._tid = 0
        self._helpers: dict[int, tuple[int, os.sched_param]] = {}   #: threads that follow the block (follow_paced)

    def __enter__(self) -> PacedPriority:
        if not sys.platform.startswith("linux") or not hasattr(os, "SCHED_RESET_ON_FORK"):
            self.refused = "real-time scheduling is a Linux feature"
            return self
        if threading.current_thread() is not threading.main_thread():
            self.refused = "only the main thread can guard a real-time thread against running away"
            return self
        policy, param = os.sched_getscheduler(0), os.sched_getparam(0)
        if policy & ~os.SCHED_RESET_ON_FORK not in (os.SCHED_OTHER, os.SCHED_BATCH):
            self.refused = "the thread already has a real-time policy (chrt): it is kept"
            return self
        limit = resource.getrlimit(resource.RLIMIT_RTTIME)
        runaway_us = int(self.runaway_cpu_s * 1e6)
        if limit[1] != resource.RLIM_INFINITY:
            runaway_us = min(runaway_us, limit[1])
        handler = signal.signal(signal.SIGXCPU, self._runaway)
        try:
            resource.setrlimit(resource.RLIMIT_RTTIME, (runaway_us, limit[1]))
            os.sched_setscheduler(0, os.SCHED_FIFO | os.SCHED_RESET_ON_FORK, os.sched_param(self.priority))
        except OSError as error:  # EPERM: no CAP_SYS_NICE and RLIMIT_RTPRIO below the priority
            resource.setrlimit(resource.RLIMIT_RTTIME, limit)
            signal.signal(signal.SIGXCPU, handler)
            self.refused = f"real-time priority not permitted ({error.strerror or error})"
            return self
        self._saved, self._tid = (policy, param, handler, limit), threading.get_native_id()
        global _paced
        _paced = self
        return self

    @property
    def active(self) -> bool:
        """The thread runs at real-time priority now."""
        return self._saved is not None and not self.demoted

    def _runaway(self, signum: int, frame: Any) -> None:
        """SIGXCPU: a real-time thread spent RUNAWAY_CPU_S without waiting; every thread of the block goes on at
        normal priority."""
        if self._saved is not None and not self.demoted:
            self.demoted = True
            os.sched_setscheduler(self._tid, self._saved[0], self._saved[1])
            self._restore_helpers()

    def _restore_helpers(self) -> None:
        for tid, (policy, param) in list(self._helpers.items()):
            self._helpers.pop(tid, None)
            try:
                os.sched_setscheduler(tid, policy, param)
            except OSError:  # the thread has ended
                pass

    def __exit__(self, *exc: object) -> None:
        if self._saved is None:
            return
        global _paced
        _paced = None  # before the helpers are restored: one that follows from now on sees it (follow_paced)
        policy, param, handler, limit = self._saved
        self._saved = None
        os.sched_setscheduler(0, policy, param)
        self._restore_helpers()
        resource.setrlimit(resource.RLIMIT_RTTIME, limit)
        signal.signal(signal.SIGXCPU, handler)


def follow_paced(below: int = 1) -> None:
    """Called by a thread the paced motion cycle can wait on through Python's interpreter lock (the plan-ahead worker,
    bench_view's old view sender): while a PacedPriority block is in force, the calling thread runs at real-time priority `below`
    under the cycle's, until the block ends. At normal priority, such a thread holding the interpreter lock when a
    busy program preempted it kept the cycle waiting however high the cycle's own priority (bench_paced_contention:
    `lateness_p99_ms_busy_realtime` against `..._helpers_normal`). The thread must wait between its jobs (a queue, a
    sleep), as the cycle does; the same runaway guard covers it. Elsewhere (no block, not permitted) nothing changes."""
    paced = _paced
    if paced is None or not paced.active:
        return
    tid = threading.get_native_id()
    if tid in paced._helpers or tid == paced._tid:
        return
    saved = (os.sched_getscheduler(0), os.sched_getparam(0))
    try:
        os.sched_setscheduler(0, os.SCHED_FIFO | os.SCHED_RESET_ON_FORK, os.sched_param(max(1, paced.priority - below)))
    except OSError:
        return
    paced._helpers[tid] = saved
    if _paced is not paced or not paced.active:  # the block ended meanwhile: it may not have seen this thread
        paced._helpers.pop(tid, None)
        os.sched_setscheduler(0, *saved)


#: The nice value a run that is not paced but drawn in a browser (`orc run --view --fast`) gives its session while it
#: runs. Linux (autogroup, `/proc/sys/kernel/sched_autogroup_enabled`) shares the cores between sessions first: a
#: browser, a session of its own, took its fair share of them against the run however low its threads' priority,
#: and its drawing threads on both cores kept the run's one busy thread from a whole core (bench_view:
#: `fast_slowdown_pct` against `..._normal_session`).
FAST_SESSION_NICE = -10
AUTOGROUP = "/proc/self/autogroup"
AUTOGROUP_ENABLED = "/proc/sys/kernel/sched_autogroup_enabled"


def session_nice() -> int | None:
    """The nice value of the calling process's session (its autogroup), None where the kernel does not group by
    session: not Linux, autogroup switched off, or a sandbox whose /proc answers with an empty or foreign line."""
    try:
        with open(AUTOGROUP_ENABLED, encoding="ascii") as enabled:
            if enabled.read().strip() != "1":
                return None
        with open(AUTOGROUP, encoding="ascii") as group:
            fields = group.read().split()  # "/autogroup-2925 nice 0"
    except OSError:
        return None
    if len(fields) != 3 or fields[1] != "nice":
        return None
    try:
        return int(fields[2])
    except ValueError:
        return None


class SessionPriority:
    """`with SessionPriority():` runs the calling process's session (its autogroup) at FAST_SESSION_NICE until the
    block ends, where it gets its nice value back. Where the kernel does not group by session, nothing changes (the
    threads' own priorities order them then); where it is not permitted (a negative nice needs CAP_SYS_NICE or an
    RLIMIT_NICE), nothing changes and `refused` says why."""

    def __init__(self, nice: int = FAST_SESSION_NICE) -> None:
        self.nice = nice
        self.refused: str | None = None
        self._saved: int | None = None

    def __enter__(self) -> SessionPriority:
        nice = session_nice()
        if nice is None or nice <= self.nice:
            return self
        cgroup = _cpu_cgroup()
        if cgroup is not None:
            self.refused = (f"the run's control group {cgroup} shares the processor by its own weight, not by "
                            "session (the session's priority would change nothing)")
            return self
        error = _write_autogroup(self.nice)
        if error is not None:  # EPERM: no CAP_SYS_NICE and no nice allowance
            self.refused = f"a higher priority for the run's session not permitted ({error.strerror or error})"
            return self
        self._saved = nice
        return self

    def __exit__(self, *exc: object) -> None:
        if self._saved is not None:
            saved, self._saved = self._saved, None
            error = _write_autogroup(saved)
            if error is not None:   # never raise here: what the run made is still to be written
                sys.stderr.write(f"orc: the session's priority could not be put back ({error.strerror or error}); "
                                 f"`echo {saved} > {AUTOGROUP}` in this terminal does it\n")


#: Linux takes one change of a session's nice value per 100 ms from a process without CAP_SYS_ADMIN, machine-wide,
#: and refuses the next with EAGAIN: a run shorter than that (or another session's change just before) must wait.
AUTOGROUP_RETRIES, AUTOGROUP_RETRY_S = 5, 0.11


def _write_autogroup(nice: int) -> OSError | None:
    """Write the session's nice value, waiting out Linux's rate limit (EAGAIN); the error that stopped it, or None."""
    for attempt in range(AUTOGROUP_RETRIES):
        try:
            with open(AUTOGROUP, "w", encoding="ascii") as group:
                group.write(str(nice))
            return None
        except BlockingIOError as error:
            if attempt == AUTOGROUP_RETRIES - 1:
                return error
            time.sleep(AUTOGROUP_RETRY_S)
        except OSError as error:
            return error
    return None


def _cpu_cgroup(proc_cgroup: str = "/proc/self/cgroup", root: str = "/sys/fs/cgroup") -> str | None:
    """The calling process's control group where its processor share is set by that group rather than by its session,
    else None. Linux applies a session's nice value only to processes in the root cpu group; a desktop whose systemd
    enabled the cpu controller for the user's slices (cgroup v2: "cpu" in a parent's cgroup.subtree_control, or a
    cgroup v1 cpu hierarchy below its root) puts the run in a group of its own."""
    try:
        with open(proc_cgroup, encoding="ascii") as lines:
            entries = [line.rstrip("\n").split(":", 2) for line in lines if line.strip()]
    except OSError:
        return None
    for entry in entries:
        if len(entry) != 3:
            continue
        _, controllers, path = entry
        if controllers and "cpu" in controllers.split(","):   # cgroup v1: the cpu hierarchy's own line
            return path if path != "/" else None
        if controllers == "" and path != "/":   # cgroup v2: cpu enabled for the children of any folder above
            parts = [part for part in path.split("/") if part]
            for depth in range(len(parts)):
                folder = os.path.join(root, *parts[:depth])
                try:
                    with open(os.path.join(folder, "cgroup.subtree_control"), encoding="ascii") as control:
                        if "cpu" in control.read().split():
                            return path
                except OSError:
                    return None
    return None
