"""`orc pendant --view`: the 3D view follows jogging, teaching, stepping and the cursor, in a real browser."""

from __future__ import annotations

import re
import shutil
import time
from pathlib import Path

import numpy as np
import pytest

from tests.pendant.support import FRAME_PROGRAM, LINE_MOVE_POS1
from tests.pendant.test_tmux import ORC, Terminal
from tests.view.support import CHROMIUM_ARGS, chromium_or_skip

pytest.importorskip("viser", reason="the 3D view is the [view] extra")

from orc_rpl.pendant.commands import run_line  # noqa: E402
from orc_rpl.pendant.robot import PendantRobot  # noqa: E402
from orc_rpl.pendant.session import PendantSession  # noqa: E402
from orc_rpl.plant.shapes import cell_poses  # noqa: E402
from orc_rpl.view.live import sim_cell  # noqa: E402
from orc_rpl.view.remote import ViewProcess  # noqa: E402
from orc_rpl.view.scene import HIGHLIGHT_RGB, HIGHLIGHT_SCALE, PATH_RGB  # noqa: E402
from orc_rpl.view.streamed import StreamedView  # noqa: E402

pytestmark = pytest.mark.sim


def _say(session: PendantSession, line: str) -> str:
    outcome = run_line(session, line)
    assert not outcome.error, outcome.text
    return outcome.text


def _world_xyz(session: PendantSession, name: str) -> tuple[float, float, float]:
    machine = session.execution.executive().machine
    pose = machine.to_world(machine.globals[name])
    return (pose.x, pose.y, pose.z)


def test_the_view_follows_the_pendant_in_a_browser(tmp_path: Path) -> None:
    executable = chromium_or_skip()
    from playwright.sync_api import sync_playwright

    path = tmp_path / "cell.rpl"
    path.write_text(FRAME_PROGRAM, encoding="utf-8")
    robot = PendantRobot.virtual()  # the servo backend: a MuJoCo cell to draw
    session = PendantSession(path, robot=robot)
    server = ViewProcess("127.0.0.1", 0)  # the server in its own process, as `orc pendant --view` has it
    try:
        live = StreamedView(server.scene, session.execution.executive(), robot)
        live.attach(session.editor.program)
        session.show_in(live)
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=executable, args=CHROMIUM_ARGS)
            page = browser.new_page(viewport={"width": 640, "height": 480})
            page.goto(server.url)
            page.get_by_text("t = ").first.wait_for(timeout=120_000)

            # the cursor on a motion: its target is highlighted
            _say(session, f":goto {LINE_MOVE_POS1}")
            scene = server.scene.snapshot()
            assert scene.positions["pos1"].scale == pytest.approx(HIGHLIGHT_SCALE)
            assert scene.positions["pos0"].scale == pytest.approx(1.0)

            # stepping the statement: the robot's links follow the plant; the path it planned is drawn
            _say(session, ":pp")
            _say(session, ":step")
            scene = server.scene.snapshot()
            poses = cell_poses(sim_cell(robot))
            for index, node in scene.moving.items():
                np.testing.assert_allclose(node.position, poses.position_m[index], atol=1e-6)
            step_move = max(session.view.lines)
            assert session.view.lines[step_move] == LINE_MOVE_POS1
            np.testing.assert_allclose(scene.paths[step_move].points[-1, 1], _world_xyz(session, "pos1"), atol=1e-3)

            # the pointer back on that statement: its motion is the blue one
            _say(session, f":goto {LINE_MOVE_POS1}")
            _say(session, ":pp")
            scene = server.scene.snapshot()
            colours = scene.paths[step_move].colors
            assert tuple(colours[0, 0]) == HIGHLIGHT_RGB
            assert all(tuple(node.colors[0, 0]) == PATH_RGB for key, node in scene.paths.items() if key != step_move)

            # jogging moves the robot in the view; teaching draws the new position, deleting it takes it away
            _say(session, ":jog world z +50mm")
            _say(session, ":goto 1")
            _say(session, ":teach corner")
            scene = server.scene.snapshot()
            poses = cell_poses(sim_cell(robot))
            for index, node in scene.moving.items():  # viser skips a move within 1e-5 relative: 10 um at 1 m
                np.testing.assert_allclose(node.position, poses.position_m[index], atol=1e-4)
            assert "corner" in scene.positions
            np.testing.assert_allclose(scene.positions["corner"].position, _world_xyz(session, "corner"), atol=1e-9)
            line = session.editor.text.splitlines().index(next(t for t in session.editor.text.splitlines()
                                                               if t.startswith("POS corner"))) + 1
            _say(session, f":goto {line}")
            scene = server.scene.snapshot()
            assert scene.positions["corner"].scale == pytest.approx(HIGHLIGHT_SCALE)
            _say(session, ":delete")
            scene = server.scene.snapshot()
            assert "corner" not in scene.positions
            assert {"pos0", "pos1", "pos2", "pos3", "base_plate"} <= set(scene.positions)

            time.sleep(1.0)  # the scene fades in
            png = page.locator("canvas").first.screenshot(timeout=120_000)
            browser.close()
        assert live.sender.error is None
    finally:
        session.close()
        live.finish()
        server.close()
    from io import BytesIO

    from PIL import Image

    pixels = np.asarray(Image.open(BytesIO(png)).convert("RGB")).astype(int)
    assert pixels.std() > 10, "the canvas is a flat colour"


@pytest.mark.skipif(shutil.which("tmux") is None, reason="tmux is not installed (apt-get install tmux)")
def test_orc_pendant_view_at_a_terminal(tmp_path: Path) -> None:
    executable = chromium_or_skip()
    from playwright.sync_api import sync_playwright

    (tmp_path / "cell.rpl").write_text(FRAME_PROGRAM, encoding="utf-8")
    terminal = Terminal("view", f"{' '.join(ORC)} pendant cell.rpl --view --view-port 0", tmp_path)
    try:
        screen = terminal.wait_for("the 3D view is at http://127.0.0.1:", 120)
        url = re.search(r"(http://127\.0\.0\.1:\d+)", screen).group(1)
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=executable, args=CHROMIUM_ARGS)
            page = browser.new_page(viewport={"width": 640, "height": 480})
            page.goto(url)
            caption = page.get_by_text(re.compile(r"TCP \(")).first
            caption.wait_for(timeout=120_000)
            z_before = float(re.search(r"TCP \(\S+, \S+, (\S+)\) mm", caption.inner_text()).group(1))
            terminal.line(":jog world z +50mm")
            terminal.wait_for("jog world z +50mm", 60)
            expected = f"{z_before + 50:.1f}"
            page.wait_for_function(f"document.body.innerText.includes(', {expected}) mm')", timeout=120_000)
            # stepping: the caption follows the program pointer
            terminal.line(f":goto {LINE_MOVE_POS1}")
            terminal.line(":pp")
            terminal.wait_for(f"program pointer at line {LINE_MOVE_POS1}", 60)
            end = time.monotonic() + 120
            while time.monotonic() < end:  # :pp's slow approach motion runs first; :step is refused while it does
                terminal.line(":step")
                time.sleep(1.0)
                if "busy:" not in terminal.screen():
                    break
            terminal.wait_for(f"paused before line {LINE_MOVE_POS1 + 1}", 120)
            page.get_by_text(f"line {LINE_MOVE_POS1 + 1}: MOVE ARM TO pos2").first.wait_for(timeout=120_000)
            browser.close()
        terminal.line(":quit!")
        terminal.wait_for("EXITED=0", 60)
    finally:
        terminal.close()
