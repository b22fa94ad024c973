"""The view's options on the command line: combinations that make no sense are usage errors before anything moves."""

from __future__ import annotations

import signal
import subprocess
import urllib.request

import pytest

from tests.view.support import ROOT, orc, read_url

PROGRAM = str(ROOT / "programs" / "online" / "thesis_4_1_move_via.rpl")


@pytest.mark.parametrize(("args", "message"), [
    (["--fast"], "--fast needs --view"),
    (["--host", "0.0.0.0"], "--host needs --view"),
    (["--view-port", "9000"], "--view-port needs --view"),
    (["--view", "--fast", "--realtime"], "--fast and --realtime contradict each other"),
    (["--view", "--view-port", "70000"], "--view-port: expected a port number 0..65535"),
    (["--view", "--host", "203.0.113.9"], "--host 203.0.113.9: cannot listen on that address"),
], ids=["fast-alone", "host-alone", "port-alone", "fast-realtime", "port-range", "foreign-address"])
def test_view_options_that_make_no_sense_exit_2(args: list[str], message: str) -> None:
    pytest.importorskip("viser", reason="the 3D view is the [view] extra")
    proc = orc("run", PROGRAM, *args)
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 2, err
    assert message in err
    assert "status:" not in err, "nothing may move"


@pytest.mark.sim
@pytest.mark.parametrize(("world", "program"), [
    ("cell_thesis.yaml", "offline/thesis_7_3.orl"),
    ("positioner_cell.yaml", "online/demo_positioner.rpl"),  # a program naming the cell's moving frames
], ids=["offline", "moving-frames"])
def test_orc_view_serves_a_world_until_interrupted(world: str, program: str) -> None:
    pytest.importorskip("viser", reason="the 3D view is the [view] extra")
    proc = orc("view", str(ROOT / "worlds" / world), str(ROOT / "programs" / program), "--view-port", "0")
    try:
        url = read_url(proc.stderr)
        assert url.startswith("http://127.0.0.1:")
        with urllib.request.urlopen(url, timeout=30) as response:
            assert response.status == 200
        proc.send_signal(signal.SIGINT)
        proc.communicate(timeout=60)
    finally:
        proc.kill()
    assert proc.returncode == 0


def test_orc_view_names_a_missing_world() -> None:
    proc = orc("view", "no_such_world.yaml")
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 2
    assert "orc view: error: world model 'no_such_world.yaml' does not exist" in err


@pytest.mark.parametrize(("args", "message"), [
    (["--host", "0.0.0.0"], "--host needs --view"),
    (["--view-port", "9000"], "--view-port needs --view"),
    (["--view", "--view-port", "70000"], "--view-port: expected a port number 0..65535"),
    (["--view", "--host", "203.0.113.9"], "--host 203.0.113.9: cannot listen on that address"),
], ids=["host-alone", "port-alone", "port-range", "foreign-address"])
def test_pendant_view_options_that_make_no_sense_exit_2(tmp_path, args: list[str], message: str) -> None:  # noqa: ANN001
    pytest.importorskip("viser", reason="the 3D view is the [view] extra")
    program = tmp_path / "cell.rpl"
    program.write_text("MOVE ARM TO HOME\n", encoding="utf-8")
    proc = orc("pendant", str(program), *args, stdin=subprocess.PIPE)
    out, err = proc.communicate(":where\n", timeout=120)
    assert proc.returncode == 2, err
    assert message in err
    assert out == "", "no line of the script ran"
