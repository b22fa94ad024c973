"""The 3D view's cost, with headless Chromium connected: its update rate, the motion cycle's lateness, the slowdown.

* `view_updates_per_s`: updates the view sent per wall-clock second during a `--view` run (paced to real time);
  target at least 30.
* `lateness_p99_ms`: how late each motion cycle ends against the real-time schedule it is paced to (wall clock minus
  the simulated clock, from the pacing's own start), 99th percentile, with the view and, as the baseline, without.
  Target at most 2 ms.
* `fast_slowdown_pct`: wall time of a `--view --fast` run against the same run without a view (best of N each);
  target at most 10 %.

Run it alone: `python benchmarks/bench_view.py [--repeats 3]` (needs chromium and the [view] extra; about a minute).
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

from orc_rpl.application.standard_behaviour import runtime_registry
from orc_rpl.executive.cell_robot import CellRobot
from orc_rpl.executive.executive import Executive
from orc_rpl.transform.loading import load_program
from orc_rpl.view.live import LiveView
from orc_rpl.view.scene import CellScene
from orc_rpl.view.server import close_server, open_server

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


def one_run(path: Path, page: Any, paced: bool, view: bool) -> dict[str, Any]:
    """Run the program once; with a view and a page, the page is (re)loaded and connected before it starts."""
    source, program = load_program(path)
    robot = CellRobot.virtual(realtime=paced)
    executive = Executive(program, robot, runtime_registry(), path=str(path), source=source, output=lambda line: None)
    server = live = None
    driven: Any = robot
    if view:
        server = open_server(port=0)
        live = LiveView(CellScene(server), executive, robot)
        live.attach(program)
        if page is not None:
            page.goto(f"http://127.0.0.1:{server.get_port()}")
            page.get_by_text("t = ").first.wait_for(timeout=120_000)
        driven = live.monitor(robot)
    probe = Lateness(driven)
    executive.machine.robot = probe
    wall = time.perf_counter()
    status = executive.run()
    wall_s = time.perf_counter() - wall
    if live is not None:
        live.finish()
    if server is not None:
        if page is not None:
            page.goto("about:blank")
        close_server(server)
    assert status == "finished", status
    return {"wall_s": wall_s, "sim_s": robot.time_s(), "late_s": np.array(probe.late_s),
            "updates": live.updates if live is not None else 0}


def _program(folder: Path, rounds: int) -> Path:
    path = folder / f"cycle_{rounds}.rpl"
    path.write_text(PROGRAM.replace("ROUNDS", str(rounds)), encoding="utf-8")
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3, help="runs of each fast variant (the best counts)")
    parser.add_argument("--paced-rounds", type=int, default=3, help="pick-and-place rounds of the paced runs")
    parser.add_argument("--fast-rounds", type=int, default=40, help="pick-and-place rounds of the fast runs")
    args = parser.parse_args()
    from playwright.sync_api import sync_playwright

    with tempfile.TemporaryDirectory() as folder, sync_playwright() as p:
        paced, fast = _program(Path(folder), args.paced_rounds), _program(Path(folder), args.fast_rounds)
        browser = p.chromium.launch(executable_path="/usr/bin/chromium", args=CHROMIUM_ARGS)
        page = browser.new_page(viewport={"width": 800, "height": 600})
        paced_view = one_run(paced, page, paced=True, view=True)
        paced_bare = one_run(paced, page, paced=True, view=False)
        paced_no_browser = one_run(paced, None, paced=True, view=True)
        # interleaved, so a change of the machine's load between them touches both alike; the best of each counts
        fast_runs = [(one_run(fast, page, paced=False, view=True), one_run(fast, page, paced=False, view=False))
                     for _ in range(args.repeats)]
        fast_view = min((r[0] for r in fast_runs), key=lambda r: r["wall_s"])
        fast_bare = min((r[1] for r in fast_runs), key=lambda r: r["wall_s"])
        browser.close()
    print(f"paced_simulated_s={paced_view['sim_s']:.3f}")
    print(f"paced_wall_s={paced_view['wall_s']:.3f}")
    print(f"view_updates_per_s={paced_view['updates'] / paced_view['wall_s']:.1f}")
    print(f"lateness_p99_ms={1000 * np.percentile(paced_view['late_s'], 99):.3f}")
    print(f"lateness_max_ms={1000 * paced_view['late_s'].max():.3f}")
    print(f"lateness_p99_ms_view_without_browser={1000 * np.percentile(paced_no_browser['late_s'], 99):.3f}")
    print(f"lateness_p99_ms_without_view={1000 * np.percentile(paced_bare['late_s'], 99):.3f}")
    print(f"fast_simulated_s={fast_view['sim_s']:.3f}")
    print(f"fast_wall_s_with_view={fast_view['wall_s']:.3f}")
    print(f"fast_wall_s_without_view={fast_bare['wall_s']:.3f}")
    print(f"fast_updates_per_s={fast_view['updates'] / fast_view['wall_s']:.1f}")
    print(f"fast_slowdown_pct={100 * (fast_view['wall_s'] / fast_bare['wall_s'] - 1):.1f}")


if __name__ == "__main__":
    main()
