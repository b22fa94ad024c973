"""The view's web server in its own process: the run's process stores samples in shared memory and sends the rare
events (a planned path, a position, a weld) into a socket.

Serialising scene updates for the browser, the websocket sends and viser's event loop all run Python; in the run's
process they held the interpreter lock the motion cycle needs (bench_view measures the difference). Here the view's
process reads the run's samples at its own rate (view/stream.py, view/drawing.py) and does the rest; the run's
process may also send whole updates down the socket (`show`, as LiveView does).
"""

from __future__ import annotations

import os
import select
import signal
import socket
import subprocess
import sys
import threading
import time
from multiprocessing.connection import Connection
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from orc_rpl.errors import OrcError, UsageError

#: The scene's methods a run may call through the socket (CellScene's; `snapshot` is answered, not called).
COMMANDS = frozenset({"add_cell", "add_object", "set_position", "show_position", "remove_positions", "add_path",
                      "extend_trace", "extend_process", "add_weld", "highlight", "set_caption", "frame_camera", "show"})
#: The run's stream (StreamedView): opened, told the tool, the program's lines and the process caption, closed.
STREAM_COMMANDS = frozenset({"stream_open", "stream_tool", "stream_lines", "stream_process", "stream_close"})
#: How long the view's process may take to start (imports, binding) before the run gives up on it.
START_TIMEOUT_S = 120.0


@dataclass(frozen=True)
class Drawn:
    """A node as the view's server has it: where it is, how large, its colour (weld spots) or its text."""

    position: np.ndarray
    wxyz: np.ndarray
    scale: float = 1.0
    color: tuple[int, int, int] | None = None


@dataclass(frozen=True)
class DrawnLine:
    """Line segments as the view's server has them (planned paths): (n, 2, 3) points, their colours, thickness."""

    points: np.ndarray
    colors: np.ndarray
    thickness: float


@dataclass(frozen=True)
class Picture:
    """What the view's server shows now, copied out of its process (tests ask for it; the run never does)."""

    moving: dict[int, Drawn] = field(default_factory=dict)
    objects: dict[str, Drawn] = field(default_factory=dict)
    positions: dict[str, Drawn] = field(default_factory=dict)
    paths: dict[int, DrawnLine] = field(default_factory=dict)
    trace_m: list[np.ndarray] = field(default_factory=list)
    welds: dict[int, Drawn] = field(default_factory=dict)
    process: dict[str, tuple[list[np.ndarray], list[np.ndarray]]] = field(default_factory=dict)
    caption: str = ""


def picture_of(scene: Any) -> Picture:
    """A plain copy of a CellScene's nodes."""
    def drawn(node: Any) -> Drawn:
        color = getattr(node, "color", None)
        return Drawn(np.array(node.position), np.array(node.wxyz), float(np.max(node.scale)),
                     None if color is None else tuple(int(c) for c in color))  # type: ignore[arg-type]

    return Picture({i: drawn(n) for i, n in scene.moving.items()}, {k: drawn(n) for k, n in scene.objects.items()},
                   {k: drawn(n) for k, n in scene.positions.items()},
                   {k: DrawnLine(np.array(n.points), np.array(n.colors), float(n.thickness)) for k, n in scene.paths.items()},
                   list(scene.trace_m), {k: drawn(n) for k, n in scene.welds.items()},
                   {k: (list(p), list(c)) for k, (p, c) in scene.process.items()},
                   scene.caption)


class RemoteScene:
    """Stands for the CellScene in the view's process: each call is one message down the socket, in order.

    Calls come from the thread that sets a view up and, for the rare events of a streamed view (a planned path, a
    position, a weld, a new tool, the process caption), from the motion cycle itself (view/live.py's Direct):
    a send there waits while the socket's buffer is full. The lock keeps the messages whole.
    """

    def __init__(self, connection: Any) -> None:
        self._connection = connection
        self._lock = threading.Lock()

    def __getattr__(self, name: str) -> Any:
        if name not in COMMANDS and name not in STREAM_COMMANDS:
            raise AttributeError(name)

        def call(*args: Any) -> None:
            with self._lock:
                self._connection.send((name, args))
        return call

    def snapshot(self) -> Picture:
        """What the server shows once every message sent so far is applied (drain the view's sender first)."""
        with self._lock:
            self._connection.send(("snapshot", ()))
            return self._connection.recv()  # type: ignore[no-any-return]

    def sync(self) -> int:
        """Wait until the server has applied every message sent so far and drawn the stream's last sample; the
        number of states it drew from the stream."""
        with self._lock:
            self._connection.send(("sync", ()))
            return self._connection.recv()  # type: ignore[no-any-return]


class ViewProcess:
    """The view's server running in a process of its own; `scene` draws in it, `url` is where a browser goes.

    The process is `python -m orc_rpl.view.remote`, not a multiprocessing child: that would import the caller's main
    script again, which a script without a `__main__` guard cannot take.
    """

    def __init__(self, host: str, port: int, shadows: bool = False, environment_map: bool = False,
                 own_session: bool = True, woken_by_run: bool = False) -> None:
        ours, theirs = socket.socketpair()
        self._notice, notice_w = os.pipe()      # a byte arrives when a browser opens the page
        options = ("shadows" if shadows else "flat") + (",environment" if environment_map else "") \
            + (",woken" if woken_by_run else "")
        # A session of its own (`own_session`): Linux shares the cores between sessions first (autogroup), and within
        # the run's session the view's process, woken 40 times a second, took the motion thread's core as an equal
        # whenever the other core was busy (a browser drawing, other programs): a `--view --fast` run waited for it
        # (bench_view: `_view_in_run_session`). In a session of its own, at the ordinary priority, it gets the cores
        # a browser would, and nothing of a run's raised priority (motion/scheduling.SessionPriority). Ctrl-C at the
        # terminal then reaches the run alone, which closes the view as before; so does the end of the run's socket.
        self._process = subprocess.Popen(
            [sys.executable, "-m", "orc_rpl.view.remote", str(theirs.fileno()), str(notice_w), host, str(port), options],
            pass_fds=(theirs.fileno(), notice_w), stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
            start_new_session=own_session)
        self.pid = self._process.pid
        theirs.close()
        os.close(notice_w)
        self._connection = Connection(ours.detach())
        try:
            if not self._connection.poll(START_TIMEOUT_S):
                raise EOFError
            kind, text = self._connection.recv()
        except EOFError:
            self._stop()
            raise OrcError("the 3D view's server did not start") from None
        if kind == "error":
            self._stop()
            raise UsageError(text)
        self.url: str = text
        self.scene = RemoteScene(self._connection)

    def wait_connected(self, timeout_s: float) -> bool:
        """Wait until a browser has opened the page (at most `timeout_s`); True when one has."""
        return bool(select.select([self._notice], [], [], timeout_s)[0])

    def close(self) -> None:
        """Stop the server and its process (what was sent before is shown first)."""
        try:
            self.scene._connection.send(("close", ()))
        except (OSError, ValueError):  # the process is already gone
            pass
        self._stop()

    def _stop(self) -> None:
        try:
            self._process.wait(timeout=30)
        except subprocess.TimeoutExpired:
            self._process.kill()
            self._process.wait()
        self._connection.close()
        os.close(self._notice)


def _serve(connection: Any, notice: int, host: str, port: int, shadows: bool, environment_map: bool = False,
           woken_by_run: bool = False) -> None:
    """The view's process: open the server, then apply the run's messages until told to close (`woken_by_run`: while
    it draws a stream, it waits on the run's socket between draws, as it did before; bench_view's baseline)."""
    from orc_rpl.view.scene import CellScene
    from orc_rpl.view.server import close_server, open_server, url_of

    try:
        server = open_server(host, port)
    except UsageError as error:
        connection.send(("error", str(error)))
        return
    server.on_client_connect(lambda client: os.write(notice, b"c"))
    scene = CellScene(server, shadows, environment_map)
    connection.send(("ready", url_of(server)))
    drawer: Any = None   #: the stream's StreamDrawer while a run streams
    next_s = time.monotonic()
    try:
        while True:
            if drawer is None:
                connection.poll(None)  # nothing to draw: wait for the run's next message
            elif woken_by_run:
                connection.poll(max(0.0, next_s - time.monotonic()))
            else:
                # While it draws a stream, this process sleeps to its next draw and then reads what the run sent
                # meanwhile: it never waits on the run's socket. A write into a socket whose reader waits wakes the
                # reader as a synchronous wake-up, which Linux serves on the writer's core: each planned path of a
                # `--view --fast` run put this process on the run's own core, where the run waited for it
                # (bench_view: `fast_motion_thread_waited_for_cpu_s` against `_view_woken_by_run`).
                time.sleep(max(0.0, next_s - time.monotonic()))
            while connection.poll(0):
                try:
                    name, args = connection.recv()
                except EOFError:  # the run's process is gone
                    return
                if name == "close":
                    return
                drawer = _apply(connection, scene, drawer, name, args)
            if drawer is not None and time.monotonic() >= next_s:
                next_s = max(next_s + drawer.period_s, time.monotonic())
                drawer.poll()
    except Exception as error:  # the view stops (the run's next message finds the socket closed); the run goes on
        sys.stderr.write(f"orc: the 3D view stopped: {error}\n")
    finally:
        if drawer is not None:
            drawer.close()
        close_server(server)


def _apply(connection: Any, scene: Any, drawer: Any, name: str, args: tuple[Any, ...]) -> Any:
    """One message of the run: a call on the scene, on the stream's drawer, or a question answered; the drawer after
    it (None once the stream is closed)."""
    from orc_rpl.view.drawing import StreamDrawer

    if name == "stream_open":
        return StreamDrawer(scene, *args)
    if name == "stream_close":
        if drawer is not None:
            drawer.poll()
            drawer.close()
        return None
    if name in STREAM_COMMANDS:
        if drawer is not None:
            getattr(drawer, f"set_{name.removeprefix('stream_')}")(*args)
    elif name in ("snapshot", "sync"):
        if drawer is not None:
            drawer.poll()
        connection.send(picture_of(scene) if name == "snapshot" else drawer.updates if drawer else 0)
    else:
        getattr(scene, name)(*args)
    return drawer


if __name__ == "__main__":
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C at the terminal is for the run, which closes the view
    from orc_rpl.view.remote import _serve as serve  # this module's own copy: what it pickles, the run can load

    fd, notice_fd, host_arg, port_arg, option_list = sys.argv[1:6]
    options = option_list.split(",")
    serve(Connection(int(fd)), int(notice_fd), host_arg, int(port_arg), "shadows" in options, "environment" in options,
          "woken" in options)
