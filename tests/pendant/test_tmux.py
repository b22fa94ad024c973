"""End to end in a real terminal (tmux): teach inside a FRAME block, save, `orc run` the result; SIGKILL and recover."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests.pendant.support import FRAME_PROGRAM, LINE_MOVE_POS1

pytestmark = pytest.mark.skipif(shutil.which("tmux") is None, reason="tmux is not installed (apt-get install tmux)")

ORC = [sys.executable, "-m", "orc_rpl"]
ROOT = Path(__file__).resolve().parents[2]


class Terminal:
    """One tmux session running a command; keys in, screen text out."""

    def __init__(self, name: str, command: str, cwd: Path) -> None:
        self.name = name
        self.socket = ["tmux", "-L", f"orc-pendant-test-{os.getpid()}-{name}"]
        env = f"PYTHONPATH={ROOT} "
        subprocess.run([*self.socket, "new-session", "-d", "-s", name, "-x", "120", "-y", "40", "-c", str(cwd),
                        f"{env}{command}; echo EXITED=$?; sleep 60"], check=True)

    def keys(self, *keys: str) -> None:
        for key in keys:
            subprocess.run([*self.socket, "send-keys", "-t", self.name, key], check=True)

    def line(self, text: str) -> None:
        self.keys(text, "Enter")

    def screen(self) -> str:
        return subprocess.run([*self.socket, "capture-pane", "-p", "-t", self.name], capture_output=True, text=True).stdout

    def wait_for(self, text: str, timeout_s: float = 15.0) -> str:
        end = time.monotonic() + timeout_s
        while time.monotonic() < end:
            screen = self.screen()
            if text in screen:
                return screen
            time.sleep(0.05)
        raise AssertionError(f"{text!r} never appeared on the screen:\n{self.screen()}")

    def pid(self) -> int:
        """The pendant's process (the shell's child running python)."""
        shell = subprocess.run([*self.socket, "list-panes", "-t", self.name, "-F", "#{pane_pid}"],
                               capture_output=True, text=True).stdout.split()[0]
        children = subprocess.run(["pgrep", "-P", shell], capture_output=True, text=True).stdout.split()
        return int(children[0])

    def close(self) -> None:
        subprocess.run([*self.socket, "kill-server"], capture_output=True)


@pytest.fixture
def program(tmp_path: Path) -> Path:
    path = tmp_path / "cell.rpl"
    path.write_text(FRAME_PROGRAM, encoding="utf-8")
    return path


def test_teach_in_a_frame_block_save_and_run_it(program: Path) -> None:
    term = Terminal("teach", f"{' '.join(ORC)} pendant {program.name} --backend kinematic", program.parent)
    try:
        term.wait_for("rpl>")
        term.line(f":goto {LINE_MOVE_POS1}")
        term.line(":exec")
        term.wait_for("done in FRAME base_plate: MOVE ARM TO pos1")
        term.line(":jog world z +20mm")
        term.wait_for("jog world z +20mm")
        term.line(":insert move pos1b")
        term.wait_for("inserted MOVE ARM TO pos1b")
        term.line(":save")
        assert "cell.rpl *" not in term.wait_for("saved cell.rpl")
        term.line(":quit")
        term.wait_for("EXITED=0")
    finally:
        term.close()
    text = program.read_text(encoding="utf-8")
    assert "POS pos1b = POSE(100mm, -100mm, 70mm, " in text and "IN base_plate\n" in text, text
    assert "    MOVE ARM TO pos1\n    MOVE ARM TO pos1b\n" in text
    done = subprocess.run([*ORC, "run", str(program)], capture_output=True, text=True, cwd=ROOT, timeout=60)
    assert done.returncode == 0, done.stderr
    assert "motions: 5" in done.stderr


def test_sigkill_after_teaching_then_the_next_start_recovers(program: Path) -> None:
    term = Terminal("kill", f"{' '.join(ORC)} pendant {program.name} --backend kinematic", program.parent)
    try:
        term.wait_for("rpl>")
        term.line(f":goto {LINE_MOVE_POS1}")
        term.line(":teach corner")
        term.wait_for("taught POS corner")
        os.kill(term.pid(), signal.SIGKILL)
        term.wait_for("EXITED=137")
    finally:
        term.close()
    assert "corner" not in program.read_text(encoding="utf-8")
    again = Terminal("recover", f"{' '.join(ORC)} pendant {program.name} --backend kinematic", program.parent)
    try:
        again.wait_for("Recover them? [Y/n]")
        again.line("y")
        again.wait_for("recovered 1 unsaved edits")
        again.line(":positions")
        screen = again.wait_for("corner")
        assert "IN base_plate" in screen.split("corner", 1)[1].split("\n", 1)[0]
        again.line(":save")
        again.wait_for("saved")
        again.line(":quit")
        again.wait_for("EXITED=0")
    finally:
        again.close()
    assert "POS corner = POSE(" in program.read_text(encoding="utf-8")
