"""The 3D view's cost, with headless Chromium connected: its update rate, the motion cycle's lateness, the slowdown.

* `view_updates_per_s`: updates the view sent per wall-clock second during a `--view` run (paced to real time);
  target at least 30.
* `lateness_p99_ms`: how late each motion cycle ends against the real-time schedule it is paced to (wall clock minus
  the simulated clock, from the pacing's own start), 99th percentile; target at most 2 ms. The paced motion cycle runs
  at real-time priority, as `orc run` asks for it (`realtime_priority=1` when the system granted it).
* `fast_slowdown_pct`: wall time of a `--view --fast` run against the same run without a view (the median of the
  ratios of N interleaved rounds); target at most 10 %.
* The benchmark browser: headless Chromium drawing WebGL with SwiftShader, whose GPU process (SwiftShader: the
  pixels a user's graphics card draws) runs at SCHED_IDLE, meant to run on the CPU time nothing else wants (with
  autogroup, only against the browser's own session: see `_gpu_idle_group`); the page's JavaScript
  (the renderer process, what a browser costs any machine) and the browser's own process run as usual and count.
  Every figure is printed for a small page (320x240, no suffix) and a large one (800x600, `_large_page`), and for the
  same Chromium as it runs by itself (`_plain_browser`, `_plain_browser_small_page`): what the view costs a machine
  without a graphics card.
* What the figures are made of, steadier than wall time on a shared machine: the CPU time the view adds to the run's
  process per update (`view_cpu_ms_per_update`, `fast_cpu_slowdown_pct`), the time the motion thread was ready to
  run but waited for a core (`fast_motion_thread_waited_for_cpu_s`), the CPU time of the view's own server
  process per update (`view_process_cpu_ms_per_update`), and the browser's: its share of the cores, its frames per
  second, its CPU per frame, and its parts: the page's JavaScript (`renderer_cpu_share`, `renderer_cpu_ms_per_update`)
  and the drawing (`gpu_cpu_share`, `gpu_cpu_ms_per_frame`); and, for each fast variant, the CPU seconds of every
  part (`fast_parts`: the run's motion thread, its plan-ahead worker and other threads, each with the time it waited
  for a core; the view's process; the browser's renderer, GPU and other processes) and how often the motion cycle
  waited for the plan-ahead worker (`fast_plan_ahead_waits`, `fast_plan_ahead_waited_s`).
* Baselines in the same run: no view (`_without_view`), the view's server with no browser
  (`_view_without_browser`), the run's process sending each update through the view's sending thread as before the
  shared-memory stream (`_sender`, and `_sender_view_without_browser`), the view drawing 30 or 15 states a second
  instead of 40 (`_30_updates_per_s`, `_15_updates_per_s`) or 2 (`_2_updates_per_s`: below the 4 a second under which the page stops rendering
  between updates), the server inside the run's process as it was before it got a process of its own
  (`_in_process`), the default light casting shadows (`_with_shadows`), the benchmark browser's GPU process in a
  cgroup marked idle (`_gpu_idle_group`: idle against every session, see idle_group; `sched_autogroup`,
  `browser_own_session` and `gpu_idle_group_placed` say whether that differs from SCHED_IDLE here and whether it could
  be done), the `--fast` run's session at its ordinary nice value instead of above the browser's (`_normal_session`;
  `fast_session_priority` says whether the raise was permitted here, and `fast_slowdown_pct_same_priority` compares
  against the run without a view at the raised priority too), the scene with viser's default environment map
  (`_with_environment_map`), the view's process in the run's session instead of a session of its own
  (`_view_in_run_session`, `_view_without_browser_in_run_session`), the view's process waiting on the run's socket
  between its draws, so that each message of the run (a planned path) woke it (`_view_woken_by_run`,
  `_view_without_browser_woken_by_run`), everything as it was before those four changes
  (`_before`: also the plan made on the worker thread in `--fast`, against the run without a view as it was), and the
  paced motion cycle at normal priority (`_normal_priority`, `_normal_priority_without_view`) or at real-time priority
  with the threads it waits on through the interpreter lock left at normal priority (`_helpers_normal`), as before
  those changes.
* Playwright's driver (the node process through which this script drives the browsers, busy relaying the page's
  events while the view sends) runs in a session of its own, as the browser does: a user's browser has no such
  driver, and in this script's session it would share the run's session and its raised priority as an equal
  (`playwright_driver_own_session`; `--driver-in-run-session` for the way it was).

The paced runs are repeated `--runs` times and their medians printed. Run it alone:
`python benchmarks/bench_view.py [--runs 3] [--repeats 5]` (needs chromium and the [view] extra; about ten minutes;
as root, or with an RLIMIT_RTPRIO of at least 10, for the real-time priority).
"""

from __future__ import annotations

import argparse
import contextlib
import os
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

import numpy as np

from orc_rpl.application.standard_behaviour import runtime_registry
from orc_rpl.executive.cell_robot import CellRobot
from orc_rpl.executive.executive import Executive
from orc_rpl.motion import scheduling
from orc_rpl.transform.loading import load_program
from orc_rpl.view.live import RATE_HZ
from orc_rpl.view.remote import ViewProcess
from orc_rpl.view.scene import CellScene
from orc_rpl.view.server import close_server, open_server, url_of
from orc_rpl.view.streamed import StreamedView
from view_sender import SenderView  # the baseline beside this file: the view before the stream

#: A pick-and-place cycle of joint and straight-line motions with zones, repeated ROUNDS times.
PROGRAM = """\
TOOL gripper = POSE(0, 0, 100mm, 0, 0, 0)
POS a = POSE(600mm, -250mm, 450mm, 0, 180deg, 0)
POS b = POSE(650mm, 250mm, 450mm, 0, 180deg, 0)
POS c = POSE(800mm, 0, 300mm, 0, 180deg, 0)
FOR i FROM 1 TO ROUNDS DO
    LMOVE gripper TO a WITH ZONE = 10mm
    MOVE gripper TO b WITH ZONE = 10mm
    LMOVE gripper TO c
ENDFOR
"""
#: Counts the page's animation frames (three.js renders the scene once in each): the browser's cost per frame drawn.
COUNT_FRAMES = """(() => { const request = window.requestAnimationFrame.bind(window); window.orcFrames = 0;
  window.requestAnimationFrame = (callback) => request((t) => { window.orcFrames += 1; callback(t); }); })()"""
CHROMIUM_ARGS = ["--no-sandbox", "--enable-unsafe-swiftshader", "--use-angle=swiftshader",
                 "--disable-background-networking", "--disable-component-update", "--no-first-run"]


class Lateness:
    """After each motion cycle: how far the wall clock is behind the schedule the pacing keeps."""

    def __init__(self, robot: Any) -> None:
        self.robot, self.late_s = robot, []
        self.dt_s, self.io = robot.dt_s, robot.io

    def tick(self) -> None:
        self.robot.tick()
        layer = self.robot.layer
        start = layer._wall_start  # where the motion layer's pacing put simulated time 0 on the wall clock
        if start is not None:
            self.late_s.append(time.perf_counter() - (start + layer.now_s()))

    def __getattr__(self, name: str) -> Any:
        return getattr(self.robot, name)


def process_cpu_s(pid: int) -> float:
    """CPU seconds (user and system) of one process now."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def waited_for_cpu_s() -> float:
    """Seconds the calling thread has been ready to run but waiting for a core (Linux schedstat: run delay)."""
    return int(Path("/proc/thread-self/schedstat").read_text().split()[1]) / 1e9


def thread_times() -> dict[int, tuple[str, float, float]]:
    """Every thread of this process now: thread id -> (its part of the run, CPU seconds, seconds it was ready to run
    but waited for a core) (Linux schedstat). Parts: "motion" (the main thread: the executive and the motion cycle),
    "plan_ahead" (the motion layer's worker), "other" (the rest: Playwright's, the view's socket)."""
    found, names = {}, {thread.native_id: thread.name for thread in threading.enumerate()}
    for entry in os.listdir("/proc/self/task"):
        try:
            run_ns, wait_ns = Path(f"/proc/self/task/{entry}/schedstat").read_text().split()[:2]
        except OSError:  # the thread has ended
            continue
        part = "motion" if int(entry) == os.getpid() else "plan_ahead" if names.get(int(entry), "").startswith("orc-plan-ahead") else "other"
        found[int(entry)] = (part, int(run_ns) / 1e9, int(wait_ns) / 1e9)
    return found


def thread_parts(before: dict[int, tuple[str, float, float]]) -> dict[str, float]:
    """CPU seconds and seconds waited for a core of each part of the run's process since `before` (thread_times)."""
    parts = {f"{part}_{kind}": 0.0 for part in ("motion", "plan_ahead", "other") for kind in ("cpu_s", "waited_s")}
    for tid, (part, cpu_s, waited_s) in thread_times().items():
        _, cpu_before, waited_before = before.get(tid, (part, 0.0, 0.0))
        parts[f"{part}_cpu_s"] += cpu_s - cpu_before
        parts[f"{part}_waited_s"] += waited_s - waited_before
    return parts


def browser_cpu_s(root: int) -> dict[str, float]:
    """CPU seconds (user and system) of every Chromium process below `root` now, by kind (Linux /proc): "renderer" (the
    page's JavaScript, three.js, the WebGL calls: what a browser on any machine spends), "gpu" (the GPU process: here
    SwiftShader drawing every pixel in software, what a graphics card does elsewhere) and "browser" (the rest)."""
    parents: dict[int, int] = {}
    times: dict[int, float] = {}
    tick_s = 1.0 / os.sysconf("SC_CLK_TCK")
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            fields = Path(f"/proc/{entry}/stat").read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        parents[int(entry)] = int(fields[1])
        times[int(entry)] = (int(fields[11]) + int(fields[12])) * tick_s
    kinds = {"renderer": 0.0, "gpu": 0.0, "browser": 0.0}
    frontier = {root}
    while frontier:
        frontier = {pid for pid, parent in parents.items() if parent in frontier}
        for pid in frontier:
            try:
                command = Path(f"/proc/{pid}/cmdline").read_bytes()  # Chromium rewrites it: one string or many
            except OSError:
                continue
            if b"chrom" not in command.split(b"\0")[0].split(b" ")[0]:
                continue  # the view's own process: counted on its own
            kind = ("renderer" if b"--type=renderer" in command else "gpu" if b"--type=gpu-process" in command
                    else "browser")
            kinds[kind] += times[pid]
    return kinds


def one_run(path: Path, page: Any, paced: bool, view: str, shadows: bool = False, environment_map: bool = False,
            slice_s: float | None = scheduling.PACED_SLICE_S, realtime: bool = True,
            helpers: bool = True, before_run: Any = None, rate_hz: float = RATE_HZ, session: bool | str = True,
            plan_ahead_worker: bool = False, own_session: bool = True, woken_by_run: bool = False,
            after_run: Any = None) -> dict[str, Any]:
    """Run the program once with `view` "process" (the product: the server in its own process, fed through shared
    memory), "sender" (the server in its own process, each update sent by the run's sending thread, as before),
    "in-process" (the server in the run's process, as before that) or "none"; with a page, it is (re)loaded and connected before the run.
    `slice_s`: the scheduler slice the paced motion cycle asks for (None: the system's default, as before);
    `realtime`: a paced run's motion cycle at real-time priority, as `orc run` asks for it (False: normal priority);
    `helpers`: the threads the cycle waits on through the interpreter lock follow its priority (False: they stay at
    normal priority, as before); `own_session`: the view's process in a session of its own, as `orc run` starts it
    (False: in the run's session, as before); `woken_by_run`: the view's process waits on the run's socket between its
    draws, as before (each message of the run wakes it)."""
    scheduling.PACED_SLICE_S = slice_s
    source, program = load_program(path)
    robot = CellRobot.virtual(realtime=paced)
    if plan_ahead_worker and robot.layer.ahead is not None:  # as before: the plan made on the worker in --fast too
        robot.layer.ahead.on_worker = True
    executive = Executive(program, robot, runtime_registry(), path=str(path), source=source, output=lambda line: None)
    server: Any = None
    live = None
    driven: Any = robot
    view_pid = None
    if view != "none":
        if view in ("process", "sender"):
            server = ViewProcess("127.0.0.1", 0, shadows, environment_map, own_session, woken_by_run)
            scene, url, view_pid = server.scene, server.url, server.pid
        else:
            server = open_server(port=0)
            scene, url = CellScene(server, shadows, environment_map), url_of(server)
        live = (StreamedView if view == "process" else SenderView)(scene, executive, robot, rate_hz=rate_hz)
        live.attach(program)
        if page is not None:
            page.goto(url)
            page.get_by_text("t = ").first.wait_for(timeout=120_000)
        driven = live.monitor(robot)
    if before_run is not None:
        before_run()
    probe = Lateness(driven)
    executive.machine.robot = probe
    view_cpu = process_cpu_s(view_pid) if view_pid is not None else 0.0
    frames = page.evaluate("window.orcFrames || 0") if page is not None and live is not None else 0
    browser_before = browser_cpu_s(os.getpid())
    threads = thread_times()
    wall, cpu, thread_cpu, waited = time.perf_counter(), time.process_time(), time.thread_time(), waited_for_cpu_s()
    follow = scheduling.follow_paced
    if not helpers:
        scheduling.follow_paced = lambda below=1: None
    try:
        # as `orc run` does: a paced run's cycle at real-time priority, a fast one's session above the browser's
        with scheduling.PacedPriority() if paced and realtime else contextlib.nullcontext(None) as priority, \
                scheduling.SessionPriority() if session == "always" or (session and live is not None and not paced) \
                else contextlib.nullcontext():
            status = executive.run()
    finally:
        scheduling.follow_paced = follow
    wall_s, cpu_s = time.perf_counter() - wall, time.process_time() - cpu
    motion_cpu_s = time.thread_time() - thread_cpu  # this thread runs the motion cycle
    motion_waited_s = waited_for_cpu_s() - waited
    parts = thread_parts(threads)
    view_cpu_s = process_cpu_s(view_pid) - view_cpu if view_pid is not None else 0.0
    browser_kinds = {kind: cpu - browser_before[kind] for kind, cpu in browser_cpu_s(os.getpid()).items()}
    frames = page.evaluate("window.orcFrames || 0") - frames if page is not None and live is not None else 0
    if after_run is not None:
        after_run()
    if live is not None:
        live.finish()
    if server is not None:
        if page is not None:
            page.goto("about:blank")
        server.close() if view in ("process", "sender") else close_server(server)
    assert status == "finished", status
    return {"wall_s": wall_s, "cpu_s": cpu_s, "motion_cpu_s": motion_cpu_s, "motion_waited_s": motion_waited_s,
            "browser_cpu_s": sum(browser_kinds.values()), "view_cpu_s": view_cpu_s,
            "renderer_cpu_s": browser_kinds["renderer"], "gpu_cpu_s": browser_kinds["gpu"], "frames": frames,
            "sim_s": robot.time_s(), "late_s": np.array(probe.late_s),
            "updates": live.updates if live is not None else 0,
            "realtime": priority is not None and priority.refused is None and not priority.demoted,
            "threads": parts, "ahead_waits": robot.planning.waited if robot.planning is not None else 0,
            "ahead_waited_s": robot.planning.waited_s if robot.planning is not None else 0.0}


def _program(folder: Path, rounds: int) -> Path:
    path = folder / f"cycle_{rounds}.rpl"
    path.write_text(PROGRAM.replace("ROUNDS", str(rounds)), encoding="utf-8")
    return path


def p99_ms(run: dict[str, Any]) -> float:
    return 1000 * float(np.percentile(run["late_s"], 99))


#: The paced variants, each run --runs times, interleaved: suffix of its figures -> (page, view, one_run's options).
#: Pages: "small" and "large" in the benchmark browser (its GPU process idle, see main), "plain_small" and
#: "plain_large" in the same Chromium as it runs by itself; None: no browser.
PACED: dict[str, tuple[str | None, str, dict[str, Any]]] = {
    "": ("small", "process", {}),
    "_large_page": ("large", "process", {}),
    "_plain_browser_small_page": ("plain_small", "process", {}),
    "_plain_browser": ("plain_large", "process", {}),
    "_view_without_browser": (None, "process", {}),
    "_sender": ("small", "sender", {}),
    "_without_view": (None, "none", {}),
    "_view_in_run_session": ("small", "process", {"own_session": False}),
    "_helpers_normal": ("plain_large", "process", {"helpers": False}),
    "_normal_priority": ("plain_large", "process", {"realtime": False}),
    "_normal_priority_without_view": (None, "none", {"realtime": False}),
}
#: The fast variants (the baseline "_without_view" is the run without a view), --repeats times, interleaved.
FAST: dict[str, tuple[str | None, str, dict[str, Any]]] = {
    "": ("small", "process", {}),
    "_large_page": ("large", "process", {}),
    "_plain_browser_small_page": ("plain_small", "process", {}),
    "_plain_browser": ("plain_large", "process", {}),
    "_without_view": (None, "none", {}),
    "_view_without_browser": (None, "process", {}),
    "_sender": ("small", "sender", {}),
    "_30_updates_per_s": ("small", "process", {"rate_hz": 30.0}),
    "_15_updates_per_s": ("small", "process", {"rate_hz": 15.0}),
    "_2_updates_per_s": ("small", "process", {"rate_hz": 2.0}),
    "_sender_view_without_browser": (None, "sender", {}),
    "_in_process": ("small", "in-process", {}),
    "_with_shadows": ("small", "process", {"shadows": True}),
    "_gpu_idle_group": ("small", "process", {"gpu_idle_group": True}),
    "_with_environment_map": ("small", "process", {"environment_map": True}),
    "_normal_session": ("small", "process", {"session": False}),
    "_view_in_run_session": ("small", "process", {"own_session": False}),
    "_view_without_browser_in_run_session": (None, "process", {"own_session": False}),
    "_view_woken_by_run": ("small", "process", {"woken_by_run": True}),
    "_view_without_browser_woken_by_run": (None, "process", {"woken_by_run": True}),
    "_without_view_session_priority": (None, "none", {"session": "always"}),
    "_before": ("small", "process", {"session": False, "environment_map": True, "plan_ahead_worker": True,
                                     "own_session": False}),
    "_without_view_before": (None, "none", {"plan_ahead_worker": True}),
}
#: The pages' sizes (CSS pixels). SwiftShader's cost per frame grows with the pixels, but far less than in proportion.
SMALL_PAGE = (320, 240)
LARGE_PAGE = (800, 600)


def chromium_processes() -> dict[int, tuple[int, bytes]]:
    """Every Chromium process now: pid -> (parent pid, command line)."""
    found = {}
    for entry in os.listdir("/proc"):
        try:
            if entry.isdigit():
                command = Path(f"/proc/{entry}/cmdline").read_bytes()
                if b"chrom" in command.split(b"\0")[0].split(b" ")[0]:
                    parent = int(Path(f"/proc/{entry}/stat").read_text().rsplit(")", 1)[1].split()[1])
                    found[int(entry)] = (parent, command)
        except OSError:
            continue
    return found


def main_processes() -> set[int]:
    """The pids of Chromium's browser processes (one per browser launched), not their children."""
    return {pid for pid, (_, command) in chromium_processes().items() if b"--type=" not in command}


def gpu_processes(browsers: set[int]) -> set[int]:
    """The GPU processes of these browsers now (started by a zygote of the browser; again if one fails)."""
    processes = chromium_processes()

    def ours(pid: int) -> bool:
        while pid in processes and pid not in browsers:
            pid = processes[pid][0]
        return pid in browsers

    return {pid for pid, (_, command) in processes.items() if b"--type=gpu-process" in command and ours(pid)}


def idle_threads(pids: set[int]) -> None:
    """Every thread of these processes at SCHED_IDLE: they run only on CPU time nothing else wants. Threads they start
    later inherit it; it is applied again before each run all the same."""
    for pid in pids:
        try:
            tasks = os.listdir(f"/proc/{pid}/task")
        except OSError:
            continue
        for task in tasks:
            try:
                os.sched_setscheduler(int(task), os.SCHED_IDLE, os.sched_param(0))
            except OSError:  # the thread has ended
                pass


#: A cgroup of the cpu controller (cgroup v1, as this machine mounts it) whose tasks run only on CPU time nothing else
#: on the machine wants (`cpu.idle`), whichever session they belong to. See idle_group.
IDLE_CGROUP = Path("/sys/fs/cgroup/cpu/orc_bench_view_idle")


def autogrouped() -> bool:
    """The kernel groups processes by session and shares the processor fairly between the groups (autogroup)."""
    try:
        return Path("/proc/sys/kernel/sched_autogroup_enabled").read_text().strip() == "1"
    except OSError:
        return False


def idle_group(pids: set[int], idle: bool) -> bool:
    """Move every thread of these processes into IDLE_CGROUP (`idle`) or back to the root cgroup; False when the system
    does not allow it (no such controller, not root).

    Why: with autogroup, a policy set on threads (SCHED_IDLE, nice) orders them only against the threads of their own
    session, and Chromium starts a session of its own: its group takes a fair share of the processor against the
    run's session however idle its GPU threads are. A cgroup marked idle is idle against every other group."""
    root = IDLE_CGROUP.parent
    try:
        if idle:
            IDLE_CGROUP.mkdir(exist_ok=True)
            (IDLE_CGROUP / "cpu.idle").write_text("1")
        target = (IDLE_CGROUP if idle else root) / "tasks"
        for pid in pids:
            for task in os.listdir(f"/proc/{pid}/task"):
                with contextlib.suppress(ProcessLookupError):  # the thread has ended
                    target.write_text(task)
    except OSError:
        return False
    return True


def _driver_in_own_session() -> None:
    """Start Playwright's driver (node, which starts the browsers) in a session of its own, like a browser a user
    starts: Linux shares the cores between sessions first, and in this script's session the driver would share the
    run's session, raised above the browser's, as an equal (see SessionPriority)."""
    import asyncio
    import types

    from playwright._impl import transport

    start = asyncio.create_subprocess_exec

    async def own_session(*args: Any, **kwargs: Any) -> Any:
        return await start(*args, **kwargs, start_new_session=True)

    # only the transport's own name for asyncio sees the change; its subprocess is the driver and nothing else
    shim = types.ModuleType("asyncio")
    shim.__dict__.update(vars(asyncio), create_subprocess_exec=own_session)
    transport.asyncio = shim  # type: ignore[attr-defined]


def driver_processes() -> set[int]:
    """The pids of Playwright's drivers below this process (`run-driver`)."""
    found = set()
    for entry in os.listdir("/proc"):
        try:
            if entry.isdigit() and b"run-driver" in Path(f"/proc/{entry}/cmdline").read_bytes():
                found.add(int(entry))
        except OSError:
            continue
    return found


def _size(text: str) -> tuple[int, int]:
    width, _, height = text.partition("x")
    return int(width), int(height)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3, help="runs of each paced variant (the medians count)")
    parser.add_argument("--repeats", type=int, default=5, help="interleaved rounds of fast runs (the median ratio counts)")
    parser.add_argument("--paced-rounds", type=int, default=3, help="pick-and-place rounds of the paced runs")
    parser.add_argument("--fast-rounds", type=int, default=40, help="pick-and-place rounds of the fast runs")
    parser.add_argument("--small-page", type=_size, default=SMALL_PAGE, metavar="WxH",
                        help="the small page's size (default 320x240)")
    parser.add_argument("--large-page", type=_size, default=LARGE_PAGE, metavar="WxH",
                        help="the large page's size (default 800x600)")
    parser.add_argument("--browser-nice", type=int, default=0,
                        help="run the browser at this nice value (a user's browser on the controller's own machine "
                             "started with `nice -n 10`); 0: as a browser normally runs")
    parser.add_argument("--driver-in-run-session", action="store_true",
                        help="leave Playwright's driver in this script's session, the run's (as before)")
    quick = parser.add_mutually_exclusive_group()
    quick.add_argument("--fast-only", metavar="SUFFIXES",
                        help="a quick look: no paced runs, and of the fast variants only these (comma-separated "
                             "suffixes, e.g. ',_gpu_idle_group'; the run without a view is always made)")
    quick.add_argument("--paced-only", metavar="SUFFIXES",
                        help="a quick look: no fast runs, and of the paced variants only these (comma-separated "
                             "suffixes, e.g. ',_without_view'; the run with the benchmark browser is always made)")
    args = parser.parse_args()
    paced_variants, fast_variants = PACED, FAST
    if args.fast_only is not None:
        chosen = set(args.fast_only.split(",")) | {"_without_view"}
        unknown = chosen - set(FAST)
        if unknown:
            parser.error(f"--fast-only: no such fast variant: {', '.join(sorted(unknown))}")
        paced_variants, fast_variants = {}, {suffix: FAST[suffix] for suffix in FAST if suffix in chosen}
    if args.paced_only is not None:
        chosen = set(args.paced_only.split(",")) | {""}
        unknown = chosen - set(PACED)
        if unknown:
            parser.error(f"--paced-only: no such paced variant: {', '.join(sorted(unknown))}")
        paced_variants, fast_variants = {suffix: PACED[suffix] for suffix in PACED if suffix in chosen}, {}
    load_before = os.getloadavg()[0]
    from playwright.sync_api import sync_playwright

    if not args.driver_in_run_session:
        _driver_in_own_session()

    with tempfile.TemporaryDirectory() as folder, sync_playwright() as p:
        paced, fast = _program(Path(folder), args.paced_rounds), _program(Path(folder), args.fast_rounds)
        executable = "/usr/bin/chromium"
        if args.browser_nice:  # every process the browser starts inherits the nice value
            executable = str(Path(folder) / "chromium-niced")
            Path(executable).write_text(f'#!/bin/sh\nexec nice -n {args.browser_nice} /usr/bin/chromium "$@"\n')
            os.chmod(executable, 0o755)
        # the benchmark browser: a user's browser draws the page's pixels on a graphics card, not on the cores the
        # run uses; here SwiftShader draws them in the GPU process, which therefore gets only CPU time nothing else
        # wants. The page's JavaScript (the renderer process) and the browser's own process run as usual: counted.
        before = main_processes()
        benchmark = p.chromium.launch(executable_path=executable, args=CHROMIUM_ARGS)
        pages: dict[str | None, Any] = {None: None}
        for name, (width, height) in (("small", args.small_page), ("large", args.large_page)):
            pages[name] = benchmark.new_page(viewport={"width": width, "height": height})
        drawing = main_processes() - before
        plain = p.chromium.launch(executable_path=executable, args=CHROMIUM_ARGS)
        for name, (width, height) in (("plain_small", args.small_page), ("plain_large", args.large_page)):
            pages[name] = plain.new_page(viewport={"width": width, "height": height})
        for name, page in pages.items():
            if page is not None:
                page.add_init_script(COUNT_FRAMES)

        idle_groups: list[bool] = []  # whether the "_gpu_idle_group" variant could be placed

        def before_run(options: dict[str, Any]) -> None:  # once the page drew
            gpus = gpu_processes(drawing)
            idle_threads(gpus)
            if options.get("gpu_idle_group"):
                idle_groups.append(autogrouped() and idle_group(gpus, True))

        def run(path: Path, page: str | None, paced: bool, view: str, options: dict[str, Any]) -> dict[str, Any]:
            one = {key: value for key, value in options.items() if key != "gpu_idle_group"}
            # out of the idle group before the page is left: starved there, the GPU process may keep it from loading
            return one_run(path, pages[page], paced, view, **one, before_run=lambda: before_run(options),
                           after_run=lambda: idle_group(gpu_processes(drawing), False) if autogrouped() else None)

        # interleaved, so a change of the machine's load between them touches every variant alike
        paced_runs: dict[str, list[dict[str, Any]]] = {suffix: [] for suffix in paced_variants}
        for _ in range(args.runs):
            for suffix, (page, view, options) in paced_variants.items():
                paced_runs[suffix].append(run(paced, page, True, view, options))
        fast_runs: dict[str, list[dict[str, Any]]] = {suffix: [] for suffix in fast_variants}
        for _ in range(args.repeats):
            for suffix, (page, view, options) in fast_variants.items():
                fast_runs[suffix].append(run(fast, page, False, view, options))
        own_session = all(os.getsid(pid) != os.getsid(0) for pid in drawing)
        driver_own_session = all(os.getsid(pid) != os.getsid(0) for pid in driver_processes())
        benchmark.close()
        plain.close()
    with contextlib.suppress(OSError):  # empty now that the browser is closed
        IDLE_CGROUP.rmdir()
    print(f"load_average_1min_before={load_before:.2f}")
    print(f"load_average_1min={os.getloadavg()[0]:.2f}")
    print(f"browser_nice={args.browser_nice}")
    print(f"small_page={'x'.join(map(str, args.small_page))}")
    print(f"large_page={'x'.join(map(str, args.large_page))}")
    print(f"sched_autogroup={int(autogrouped())}")
    print(f"browser_own_session={int(own_session)}")
    print(f"playwright_driver_own_session={int(driver_own_session)}")
    print(f"gpu_idle_group_placed={int(bool(idle_groups) and all(idle_groups))}")
    with scheduling.SessionPriority() as session:  # what a `--view --fast` run gets (1: its session's nice lowered)
        print(f"fast_session_priority={int(session.refused is None and autogrouped())}")
    if paced_runs:
        print(f"realtime_priority={int(all(r['realtime'] for r in paced_runs['']))}")
        print(f"paced_simulated_s={paced_runs[''][0]['sim_s']:.3f}")
    for suffix, runs in paced_runs.items():
        _paced_figures(runs, suffix, PACED[suffix][0] is not None)
    if not fast_runs:
        return
    print(f"fast_simulated_s={fast_runs['_without_view'][0]['sim_s']:.3f}")
    baseline = fast_runs.pop("_without_view")
    print(f"fast_wall_s_without_view={np.median([r['wall_s'] for r in baseline]):.3f}")
    print(f"fast_motion_thread_cpu_s_without_view={np.median([r['motion_cpu_s'] for r in baseline]):.3f}")
    print(f"fast_motion_thread_waited_for_cpu_s_without_view={np.median([r['motion_waited_s'] for r in baseline]):.3f}")
    _fast_parts(baseline, "_without_view")
    # other baselines: without a view at the session priority the view's run gets (on a machine other programs keep
    # busy, the raised priority also takes the cores from them, which the ordinary baseline does not), and the run
    # without a view as it was before (the plan made on the worker thread in --fast too)
    others = {name: fast_runs.pop(f"_without_view{name}", None) for name in ("_session_priority", "_before")}
    for suffix, runs in fast_runs.items():
        _fast_figures(list(zip(runs, (others["_before"] or baseline) if suffix == "_before" else baseline)), suffix,
                      FAST[suffix][0] is not None)
    for name, runs in others.items():
        if runs is not None:
            print(f"fast_wall_s_without_view{name}={np.median([r['wall_s'] for r in runs]):.3f}")
            _fast_parts(runs, f"_without_view{name}")
    # every variant whose run raised its session's priority, against the run without a view raised alike
    raised = [suffix for suffix in fast_runs if FAST[suffix][1] != "none" and FAST[suffix][2].get("session", True)]
    for suffix in raised if others["_session_priority"] is not None else []:
        slowdowns = [100 * (v["wall_s"] / b["wall_s"] - 1) for v, b in zip(fast_runs[suffix], others["_session_priority"])]
        print(f"fast_slowdown_pct_same_priority_runs{suffix}={','.join(f'{x:.1f}' for x in slowdowns)}")
        print(f"fast_slowdown_pct_same_priority{suffix}={np.median(slowdowns):.1f}")


def _paced_figures(runs: list[dict[str, Any]], suffix: str, browser: bool) -> None:
    """The figures of one paced variant's runs."""
    median = np.median
    print(f"lateness_p99_ms{suffix}={median([p99_ms(r) for r in runs]):.3f}")
    print(f"lateness_p99_ms_runs{suffix}={','.join(f'{p99_ms(r):.3f}' for r in runs)}")
    print(f"lateness_max_ms{suffix}={median([1000 * r['late_s'].max() for r in runs]):.3f}")
    if runs[0]["updates"]:
        print(f"view_updates_per_s{suffix}={median([r['updates'] / r['wall_s'] for r in runs]):.1f}")
    if browser:
        _browser_figures(runs, suffix, "paced")


def _browser_figures(runs: list[dict[str, Any]], suffix: str, kind: str) -> None:
    """What the browser spent: per update, per frame (all its processes, then the page's renderer and the GPU
    process apart), its frames per second and its share of the cores."""
    median = np.median
    print(f"browser_cpu_ms_per_update_{kind}{suffix}={median([1000 * r['browser_cpu_s'] / r['updates'] for r in runs]):.2f}")
    print(f"browser_frames_per_s_{kind}{suffix}={median([r['frames'] / r['wall_s'] for r in runs]):.1f}")
    for part in ("browser", "gpu"):
        per_frame = median([1000 * r[f"{part}_cpu_s"] / max(r["frames"], 1) for r in runs])
        print(f"{part}_cpu_ms_per_frame_{kind}{suffix}={per_frame:.1f}")
    # the page's JavaScript works per update (decoding, the scene tree) and per frame (three.js): not per frame alone
    print(f"renderer_cpu_ms_per_update_{kind}{suffix}={median([1000 * r['renderer_cpu_s'] / r['updates'] for r in runs]):.2f}")
    print(f"browser_cpu_share_{kind}{suffix}={median([r['browser_cpu_s'] / r['wall_s'] for r in runs]):.2f}")
    for part in ("renderer", "gpu"):
        print(f"{part}_cpu_share_{kind}{suffix}={median([r[f'{part}_cpu_s'] / r['wall_s'] for r in runs]):.2f}")


def _fast_parts(runs: list[dict[str, Any]], suffix: str) -> None:
    """Where a fast variant's CPU went, part by part (the median seconds of each): the run's threads (CPU time and time
    waited for a core), the view's process, the browser's processes; and how often the motion cycle waited for the
    plan-ahead worker (in simulated time it waits for a plan the worker has not finished: motion/ahead.py)."""
    median = np.median
    parts = {key: median([r["threads"][key] for r in runs]) for key in runs[0]["threads"]}
    parts |= {f"{part}_cpu_s": median([r[f"{part}_cpu_s"] for r in runs]) for part in ("view", "renderer", "gpu")}
    parts["browser_rest_cpu_s"] = median([r["browser_cpu_s"] - r["renderer_cpu_s"] - r["gpu_cpu_s"] for r in runs])
    print(f"fast_parts{suffix}={','.join(f'{key}:{value:.3f}' for key, value in parts.items())}")
    print(f"fast_plan_ahead_waits{suffix}={median([r['ahead_waits'] for r in runs]):.0f}")
    print(f"fast_plan_ahead_waited_s{suffix}={median([r['ahead_waited_s'] for r in runs]):.3f}")


def _fast_figures(pairs: list[tuple[dict[str, Any], dict[str, Any]]], suffix: str, browser: bool) -> None:
    """The fast figures of (with the view, without a view) pairs."""
    median = np.median
    print(f"fast_wall_s_with_view{suffix}={median([v['wall_s'] for v, _ in pairs]):.3f}")
    print(f"fast_updates_per_s{suffix}={median([v['updates'] / v['wall_s'] for v, _ in pairs]):.1f}")
    extra_cpu_ms = [1000 * (v["cpu_s"] - b["cpu_s"]) / v["updates"] for v, b in pairs]
    print(f"view_cpu_ms_per_update{suffix}={median(extra_cpu_ms):.2f}")
    if suffix != "_in_process":
        print(f"view_process_cpu_ms_per_update{suffix}={median([1000 * v['view_cpu_s'] / v['updates'] for v, _ in pairs]):.2f}")
    print(f"fast_cpu_slowdown_pct{suffix}={100 * median([v['cpu_s'] / b['cpu_s'] - 1 for v, b in pairs]):.1f}")
    # the motion thread's own CPU time: what the view costs the cycle itself, the other threads of the run apart
    print(f"fast_motion_thread_cpu_s{suffix}={median([v['motion_cpu_s'] for v, _ in pairs]):.3f}")
    print(f"fast_motion_thread_cpu_slowdown_pct{suffix}="
          f"{100 * median([v['motion_cpu_s'] / b['motion_cpu_s'] - 1 for v, b in pairs]):.1f}")
    # ready to run, but no core free for it: what a program competing for the cores costs the run
    print(f"fast_motion_thread_waited_for_cpu_s{suffix}={median([v['motion_waited_s'] for v, _ in pairs]):.3f}")
    _fast_parts([v for v, _ in pairs], suffix)
    slowdowns = [100 * (v["wall_s"] / b["wall_s"] - 1) for v, b in pairs]
    print(f"fast_slowdown_pct_runs{suffix}={','.join(f'{x:.1f}' for x in slowdowns)}")
    print(f"fast_slowdown_pct{suffix}={median(slowdowns):.1f}")
    if browser:
        _browser_figures([v for v, _ in pairs], suffix, "fast")


if __name__ == "__main__":
    main()
