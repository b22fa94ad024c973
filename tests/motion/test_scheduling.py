"""A paced motion cycle at real-time priority: granted or refused with a reason, never passed on, never left behind."""

from __future__ import annotations

import multiprocessing
import os
import shutil
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from orc_rpl.motion import scheduling

ROOT = Path(__file__).resolve().parents[2]
LINUX = sys.platform.startswith("linux")


def _granted(priority: scheduling.PacedPriority) -> None:
    if priority.refused is not None:
        pytest.skip(f"this machine refuses real-time priority ({priority.refused}): the refusal is tested instead")


def _policy_of_child(queue: multiprocessing.Queue) -> None:
    queue.put(os.sched_getscheduler(0))


@pytest.mark.skipif(not LINUX, reason="real-time scheduling is a Linux feature")
def test_the_block_runs_the_thread_real_time_and_gives_the_policy_back() -> None:
    before = (os.sched_getscheduler(0), os.sched_getparam(0).sched_priority)
    with scheduling.PacedPriority() as priority:
        _granted(priority)
        assert priority.active
        assert os.sched_getscheduler(0) & ~os.SCHED_RESET_ON_FORK == os.SCHED_FIFO
        assert os.sched_getparam(0).sched_priority == scheduling.PACED_PRIORITY
    assert not priority.active
    assert (os.sched_getscheduler(0), os.sched_getparam(0).sched_priority) == before


@pytest.mark.skipif(not LINUX, reason="real-time scheduling is a Linux feature")
def test_threads_and_processes_started_inside_run_at_normal_priority() -> None:
    """A busy process forked from a real-time thread inherited its policy and starved the machine: no longer."""
    seen: list[int] = []
    context = multiprocessing.get_context("fork")
    queue = context.Queue()
    with scheduling.PacedPriority() as priority:
        _granted(priority)
        thread = threading.Thread(target=lambda: seen.append(os.sched_getscheduler(0)))
        thread.start()
        thread.join()
        child = context.Process(target=_policy_of_child, args=(queue,))
        child.start()
        child.join(timeout=60)
    assert seen == [os.SCHED_OTHER]
    assert queue.get(timeout=10) == os.SCHED_OTHER


@pytest.mark.skipif(not LINUX, reason="real-time scheduling is a Linux feature")
def test_a_helper_follows_the_block_just_below_and_is_put_back_when_it_ends() -> None:
    inside: list[tuple[int, int]] = []
    go_on = threading.Event()
    checked = threading.Event()

    def helper() -> None:
        scheduling.follow_paced()
        inside.append((os.sched_getscheduler(0) & ~os.SCHED_RESET_ON_FORK, os.sched_getparam(0).sched_priority))
        checked.set()
        go_on.wait(timeout=60)  # a helper waits between its jobs

    with scheduling.PacedPriority() as priority:
        _granted(priority)
        thread = threading.Thread(target=helper)
        thread.start()
        assert checked.wait(timeout=60)
        tid = thread.native_id
    after = os.sched_getscheduler(tid)
    go_on.set()
    thread.join()
    assert inside == [(os.SCHED_FIFO, scheduling.PACED_PRIORITY - 1)]
    assert after == os.SCHED_OTHER


@pytest.mark.skipif(not LINUX, reason="real-time scheduling is a Linux feature")
def test_a_thread_that_computes_without_waiting_is_put_back_to_normal_priority() -> None:
    with scheduling.PacedPriority(runaway_cpu_s=0.05) as priority:
        _granted(priority)
        start = time.thread_time()  # this thread's time: other threads of the test process may be busy too
        while not priority.demoted and time.thread_time() - start < 10.0:  # a runaway, bounded for the test
            pass
        assert priority.demoted
        assert os.sched_getscheduler(0) == os.SCHED_OTHER
    assert os.sched_getscheduler(0) == os.SCHED_OTHER


def test_a_thread_other_than_the_main_one_is_refused_with_a_reason() -> None:
    results: list[scheduling.PacedPriority] = []

    def enter() -> None:
        with scheduling.PacedPriority() as priority:
            results.append(priority)

    thread = threading.Thread(target=enter)
    thread.start()
    thread.join()
    assert results[0].refused is not None and not results[0].active


@pytest.mark.skipif(not LINUX or shutil.which("setpriv") is None, reason="needs Linux and setpriv (util-linux)")
def test_orc_run_says_when_real_time_priority_is_refused(tmp_path: Path) -> None:
    """Without CAP_SYS_NICE (an ordinary user) the paced run goes on at normal priority and says so."""
    program = tmp_path / "wait.rpl"
    program.write_text("WAIT 0.05s\n", encoding="utf-8")
    command = ["setpriv", "--inh-caps", "-sys_nice", "--bounding-set", "-sys_nice",
               sys.executable, "-m", "orc_rpl", "run", str(program), "--realtime"]
    proc = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, timeout=300)
    if proc.returncode != 0 and "setpriv" in proc.stderr:
        pytest.skip(f"setpriv cannot drop the capability here: {proc.stderr.strip()}")
    assert proc.returncode == 0, proc.stderr
    assert "orc run: the motion cycle runs at normal priority: real-time priority not permitted" in proc.stderr


@pytest.mark.skipif(scheduling.session_nice() is None, reason="the kernel does not group processes by session (autogroup)")
def test_a_fast_run_raises_its_session_and_gives_the_nice_value_back() -> None:
    before = scheduling.session_nice()
    assert before is not None
    with scheduling.SessionPriority() as priority:
        if priority.refused is not None:  # an ordinary user without an RLIMIT_NICE: said, and nothing changed
            assert "not permitted" in priority.refused
            assert scheduling.session_nice() == before
        else:
            assert scheduling.session_nice() == min(before, scheduling.FAST_SESSION_NICE)
    assert scheduling.session_nice() == before


@pytest.mark.skipif(scheduling.session_nice() is None or shutil.which("setpriv") is None,
                    reason="needs the kernel's session groups (autogroup) and setpriv (util-linux)")
def test_orc_run_view_fast_says_when_the_session_priority_is_refused(tmp_path: Path) -> None:
    """Without CAP_SYS_NICE (an ordinary user) a `--view --fast` run goes on at its session's priority and says so."""
    pytest.importorskip("viser", reason="the 3D view is the [view] extra")
    before = scheduling.session_nice()
    program = tmp_path / "wait.rpl"
    program.write_text("WAIT 0.05s\n", encoding="utf-8")
    command = ["setpriv", "--inh-caps", "-sys_nice", "--bounding-set", "-sys_nice",
               sys.executable, "-m", "orc_rpl", "run", str(program), "--view", "--fast", "--view-port", "0"]
    proc = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, timeout=300, stdin=subprocess.DEVNULL)
    if proc.returncode != 0 and "setpriv" in proc.stderr:
        pytest.skip(f"setpriv cannot drop the capability here: {proc.stderr.strip()}")
    assert proc.returncode == 0, proc.stderr
    assert "orc run: the run keeps its priority: a higher priority for the run's session not permitted" in proc.stderr
    assert scheduling.session_nice() == before


class _RateLimitedGroup:
    """`open` for scheduling's session file that refuses the first `refusals` writes as Linux's rate limit does."""

    def __init__(self, refusals: int) -> None:
        self.refusals, self.written = refusals, []

    def __call__(self, path: str, mode: str = "r", encoding: str | None = None) -> "_RateLimitedGroup":
        if "w" in mode and self.refusals > 0:
            self.refusals -= 1
            raise BlockingIOError(11, "Resource temporarily unavailable")
        return self

    def __enter__(self) -> "_RateLimitedGroup":
        return self

    def __exit__(self, *exc: object) -> None:
        return None

    def write(self, text: str) -> None:
        self.written.append(text)


def test_a_session_change_refused_by_the_rate_limit_is_made_again_and_a_failed_restore_never_raises(monkeypatch, capsys) -> None:
    monkeypatch.setattr(scheduling, "AUTOGROUP_RETRY_S", 0.0)
    group = _RateLimitedGroup(refusals=scheduling.AUTOGROUP_RETRIES - 1)
    monkeypatch.setattr(scheduling, "open", group, raising=False)
    assert scheduling._write_autogroup(-10) is None and group.written == ["-10"]
    priority = scheduling.SessionPriority()
    priority._saved = 0   # as after a granted __enter__
    monkeypatch.setattr(scheduling, "open", _RateLimitedGroup(refusals=scheduling.AUTOGROUP_RETRIES), raising=False)
    priority.__exit__(None, None, None)   # a run that ended within Linux's 100 ms: said, not raised
    assert "could not be put back" in capsys.readouterr().err and priority._saved is None


@pytest.mark.parametrize(("enabled", "group", "expected"), [
    ("1\n", "/autogroup-2925 nice 0\n", 0),
    ("1\n", "/autogroup-2925 nice -10\n", -10),
    ("0\n", "/autogroup-2925 nice 0\n", None),   # autogroup switched off
    ("1\n", "", None),                            # a sandbox's /proc that answers with nothing (seen in CI)
    ("1\n", "/autogroup-2925\n", None),
    ("1\n", "/autogroup-2925 nice high\n", None),
    (None, None, None),                           # not Linux
])
def test_the_session_nice_value_is_read_or_none_and_an_odd_proc_never_raises(
        tmp_path: Path, monkeypatch, enabled: str | None, group: str | None, expected: int | None) -> None:
    for name, text in (("AUTOGROUP_ENABLED", enabled), ("AUTOGROUP", group)):
        path = tmp_path / name
        if text is not None:
            path.write_text(text, encoding="ascii")
        monkeypatch.setattr(scheduling, name, str(path))
    assert scheduling.session_nice() == expected
    if expected is None:   # nothing to raise: the run goes on as it is, and says nothing
        with scheduling.SessionPriority() as priority:
            assert priority.refused is None and priority._saved is None


@pytest.mark.parametrize(("lines", "subtree", "expected"), [
    ("1:cpu,cpuacct:/\n0::/\n", None, None),                                    # cgroup v1, the root cpu group
    ("1:cpu,cpuacct:/user.slice\n", None, "/user.slice"),                       # v1, a group of its own
    ("0::/user.slice/user-1000.slice/session-2.scope\n", "cpu memory", "/user.slice/user-1000.slice/session-2.scope"),
    ("0::/user.slice/user-1000.slice/session-2.scope\n", "memory pids", None),  # v2 without the cpu controller
])
def test_a_cpu_group_other_than_the_root_is_found_where_the_session_priority_would_change_nothing(
        tmp_path: Path, lines: str, subtree: str | None, expected: str | None) -> None:
    proc_cgroup = tmp_path / "cgroup"
    proc_cgroup.write_text(lines, encoding="ascii")
    root = tmp_path / "fs"
    for folder in (root, root / "user.slice", root / "user.slice" / "user-1000.slice"):
        folder.mkdir(parents=True, exist_ok=True)
        (folder / "cgroup.subtree_control").write_text("memory pids\n" if folder != root or subtree is None else subtree)
    assert scheduling._cpu_cgroup(str(proc_cgroup), str(root)) == expected
