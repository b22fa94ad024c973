"""The view's server process: a session of its own, and gone when the run that started it is gone."""

from __future__ import annotations

import os
import signal
import time
import urllib.error
import urllib.request

import pytest

from tests.view.support import ROOT, orc, read_url

PROGRAM = str(ROOT / "programs" / "online" / "thesis_4_1_move_via.rpl")


def test_the_view_process_runs_in_a_session_of_its_own() -> None:
    """Linux shares the cores between sessions first: a `--view --fast` run's raised session must not carry the view."""
    pytest.importorskip("viser", reason="the 3D view is the [view] extra")
    from orc_rpl.view.remote import ViewProcess

    server = ViewProcess("127.0.0.1", 0)
    try:
        assert os.getsid(server.pid) == server.pid, "the view's process leads a session of its own"
        assert os.getsid(server.pid) != os.getsid(0)
    finally:
        server.close()


def _answers(url: str) -> bool:
    try:
        with urllib.request.urlopen(url, timeout=5) as response:
            return response.status == 200
    except (urllib.error.URLError, ConnectionError, TimeoutError):
        return False


@pytest.mark.sim
def test_the_view_stops_serving_when_its_run_is_killed() -> None:
    """Outside the terminal's process group, the view's process still ends with its run (SIGKILL: no cleanup ran)."""
    pytest.importorskip("viser", reason="the 3D view is the [view] extra")
    proc = orc("run", PROGRAM, "--view", "--view-port", "0")  # paced to real time: still running when killed
    try:
        url = read_url(proc.stderr)
        assert _answers(url)
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=60)
        deadline = time.monotonic() + 60  # a generous bound for a busy machine: the assertion is that it ends
        while _answers(url) and time.monotonic() < deadline:
            time.sleep(0.2)
        assert not _answers(url), "the view's process outlived its run"
    finally:
        proc.kill()
        proc.communicate(timeout=60)
