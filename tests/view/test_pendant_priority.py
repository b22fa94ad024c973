"""`orc pendant --view` paces its motion to the wall clock beside a browser: at real-time priority, as `orc run` does."""

from __future__ import annotations

import os
import shutil
import sys
from pathlib import Path

import pytest

from tests.pendant.support import FRAME_PROGRAM
from tests.pendant.test_tmux import ORC, Terminal

pytest.importorskip("viser", reason="the 3D view is the [view] extra")

LINUX = sys.platform.startswith("linux")
needs_tmux = pytest.mark.skipif(shutil.which("tmux") is None, reason="tmux is not installed (apt-get install tmux)")


@needs_tmux
@pytest.mark.skipif(not LINUX, reason="real-time scheduling is a Linux feature")
def test_the_pendant_view_runs_its_motion_cycle_at_real_time_priority_until_it_quits(tmp_path: Path) -> None:
    (tmp_path / "cell.rpl").write_text(FRAME_PROGRAM, encoding="utf-8")
    terminal = Terminal("rt", f"{' '.join(ORC)} pendant cell.rpl --view --view-port 0 --backend kinematic", tmp_path)
    try:
        screen = terminal.wait_for("the 3D view is at http://127.0.0.1:", 120)
        pid = terminal.pid()
        if "runs at normal priority" in screen:
            pytest.skip("this machine refuses real-time priority: the refusal is tested instead")
        # the pendant's main thread paces the motion (its pump): real-time, and what it starts is not
        assert os.sched_getscheduler(pid) & ~os.SCHED_RESET_ON_FORK == os.SCHED_FIFO
        assert os.sched_getscheduler(pid) & os.SCHED_RESET_ON_FORK
        terminal.line(":jog world z +50mm")
        terminal.wait_for("jog world z +50mm", 60)
        terminal.line(":quit!")
        terminal.wait_for("EXITED=0", 60)
    finally:
        terminal.close()


@needs_tmux
@pytest.mark.skipif(not LINUX or shutil.which("setpriv") is None, reason="needs Linux and setpriv (util-linux)")
def test_the_pendant_view_says_when_real_time_priority_is_refused(tmp_path: Path) -> None:
    """Without CAP_SYS_NICE (an ordinary user) the pendant goes on at normal priority and says so."""
    (tmp_path / "cell.rpl").write_text(FRAME_PROGRAM, encoding="utf-8")
    command = (f"setpriv --inh-caps -sys_nice --bounding-set -sys_nice {' '.join(ORC)} pendant cell.rpl --view "
               "--view-port 0 --backend kinematic")
    terminal = Terminal("refused", command, tmp_path)
    try:
        screen = terminal.wait_for("the 3D view is at http://127.0.0.1:", 120)
        if "setpriv" in screen:
            pytest.skip(f"setpriv cannot drop the capability here: {screen.strip()}")
        terminal.wait_for("orc pendant: the motion cycle runs at normal priority: real-time priority not permitted", 30)
        terminal.line(":quit!")
        terminal.wait_for("EXITED=0", 60)
    finally:
        terminal.close()
