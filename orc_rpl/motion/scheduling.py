"""The motion cycle's place in the operating system's scheduler: a cycle paced to the wall clock asks for short slices."""

from __future__ import annotations

import ctypes
import os
import platform
import sys

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
