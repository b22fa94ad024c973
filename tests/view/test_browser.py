"""The 3D view in a real browser: headless Chromium loads the page during a run; the scene is where the run says."""

from __future__ import annotations

import os
import pty
import re
import select
import subprocess
import sys
import time
import urllib.request
from urllib.parse import urlsplit

import numpy as np
import pytest

from tests.view.support import CHROMIUM_ARGS, ROOT, chromium_or_skip, orc, read_url

pytest.importorskip("viser", reason="the 3D view is the [view] extra")

from orc_rpl.application.standard_behaviour import runtime_registry  # noqa: E402
from orc_rpl.executive.cell_robot import CellRobot  # noqa: E402
from orc_rpl.executive.executive import Executive  # noqa: E402
from orc_rpl.plant.shapes import cell_poses  # noqa: E402
from orc_rpl.transform.loading import load_program  # noqa: E402
from orc_rpl.view.live import sim_cell  # noqa: E402
from orc_rpl.view.remote import ViewProcess  # noqa: E402
from orc_rpl.view.streamed import StreamedView  # noqa: E402
from orc_rpl.world.pose import shown_pose  # noqa: E402

pytestmark = pytest.mark.sim

PROGRAM = ROOT / "programs" / "online" / "demo_any_robot.rpl"


def _canvas_pixels(page) -> np.ndarray:  # type: ignore[no-untyped-def]
    from io import BytesIO

    from PIL import Image

    png = page.locator("canvas").first.screenshot(timeout=120_000)
    return np.asarray(Image.open(BytesIO(png)).convert("RGB")).astype(int)


def test_browser_shows_the_run_where_the_recording_says() -> None:
    executable = chromium_or_skip()
    from playwright.sync_api import sync_playwright

    source, program = load_program(PROGRAM)
    registry = runtime_registry()
    robot = CellRobot.virtual(record=True)
    executive = Executive(program, robot, registry, path=str(PROGRAM), source=source, output=lambda line: None)
    server = ViewProcess("127.0.0.1", 0)  # the server in its own process, as `orc run --view` has it
    try:
        view = StreamedView(server.scene, executive, robot)
        view.attach(program)
        foreign: list[str] = []
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=executable, args=CHROMIUM_ARGS)
            page = browser.new_page(viewport={"width": 640, "height": 480})
            page.on("request", lambda r: None if urlsplit(r.url).hostname in (None, "127.0.0.1") else foreign.append(r.url))
            page.goto(server.url)
            page.get_by_text("t = ").first.wait_for(timeout=120_000)  # the page is connected: the caption arrived
            view.monitor(robot)
            assert executive.run() == "finished"
            view.finish()
            page.get_by_text(f"t = {robot.time_s():.2f} s").first.wait_for(timeout=120_000)  # the last update arrived
            # the measured TCP, shown the one way orc run's summary shows it
            tcp_text = shown_pose(robot.tcp_pose(executive.machine.last_tool)).text()
            page.get_by_text(f"TCP {tcp_text}").first.wait_for(timeout=120_000)
            time.sleep(1.0)  # the scene fades in
            pixels = _canvas_pixels(page)
            browser.close()
        shown = server.scene.snapshot()  # what the server's scene holds
    finally:
        server.close()

    assert foreign == [], "the page asked for something beyond this machine"
    # not blank: the picture has many colours, and the robot's orange links are in it
    assert pixels.std() > 10, "the canvas is a flat colour"
    orange = (pixels[..., 0] - pixels[..., 2] > 60) & (pixels[..., 0] > 150)
    assert orange.mean() > 0.005, "no robot link in the picture"

    # the robot's links: where the plant has them at the end of the run
    poses = cell_poses(sim_cell(robot))
    assert shown.moving, "the robot's links are in the scene"
    for index, node in shown.moving.items():
        np.testing.assert_allclose(node.position, poses.position_m[index], atol=1e-6)
        np.testing.assert_allclose(np.abs(np.dot(node.wxyz, poses.wxyz[index])), 1.0, atol=1e-6)
    # the TCP trace ends where the recording's last measured joints put the gripper's TCP
    recording = robot.layer.logger.recording()
    tool = executive.machine.last_tool.matrix()
    expected_tcp = robot.layer.fk(recording.signals["q"][-1], tool)[:3, 3]
    np.testing.assert_allclose(shown.trace_m[-1], expected_tcp, atol=1e-6)
    # the declared positions, where the program puts them
    assert set(shown.positions) == {"tray", "above_tray", "slot1", "slot2"}
    slot1 = executive.machine.to_world(executive.value("slot1"))
    np.testing.assert_allclose(shown.positions["slot1"].position, (slot1.x, slot1.y, slot1.z), atol=1e-9)
    # the planned paths: one per motion, each drawn before it ran; the last ends at the last target
    assert len(shown.paths) == executive.motions
    last_path = shown.paths[max(shown.paths)]
    above = executive.machine.to_world(executive.value("above_tray"))
    np.testing.assert_allclose(last_path.points[-1, 1], (above.x, above.y, above.z), atol=1e-4)


def test_orc_run_view_serves_the_page_on_this_machine_only() -> None:
    proc = orc("run", str(PROGRAM), "--view", "--view-port", "0")
    try:
        url = read_url(proc.stderr)
        assert url.startswith("http://127.0.0.1:")
        with urllib.request.urlopen(url, timeout=30) as response:
            assert response.status == 200
            assert b"<html" in response.read(2000).lower()
        out, err = proc.communicate(timeout=300)
    finally:
        proc.kill()
    assert proc.returncode == 0, err
    assert "moved 2 parts" in out
    assert "status: finished" in err


def test_at_a_terminal_the_run_waits_for_the_browser_and_the_page_stays_open_until_enter() -> None:
    executable = chromium_or_skip()
    from playwright.sync_api import sync_playwright

    master, slave = pty.openpty()
    proc = subprocess.Popen([sys.executable, "-m", "orc_rpl", "run", str(ROOT / "programs" / "online" / "thesis_4_1_move_via.rpl"),
                             "--view", "--view-port", "0"], cwd=ROOT, stdin=slave, stdout=slave, stderr=slave, close_fds=True)
    os.close(slave)
    seen = bytearray()

    def read_until(pattern: bytes) -> re.Match[bytes]:
        deadline = time.monotonic() + 300
        while time.monotonic() < deadline:
            match = re.search(pattern, seen)
            if match:
                return match
            if select.select([master], [], [], 0.5)[0]:
                try:
                    seen.extend(os.read(master, 4096))
                except OSError:
                    break
        raise AssertionError(f"never saw {pattern!r} in {bytes(seen[-400:])!r}")

    try:
        url = read_until(rb"(http://127\.0\.0\.1:\d+)").group(1).decode()
        read_until(rb"the run starts when it connects")
        assert b"status:" not in seen, "nothing moves before the page is open"
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=executable, args=CHROMIUM_ARGS)
            page = browser.new_page()
            page.goto(url)
            read_until(rb"stays open until you press Enter")
            assert b"status: finished" in seen, "the summary comes before the question"
            with urllib.request.urlopen(url, timeout=30) as response:  # still served after the run
                assert response.status == 200
            os.write(master, b"\n")
            assert proc.wait(timeout=60) == 0
            browser.close()
    finally:
        proc.kill()
        os.close(master)
