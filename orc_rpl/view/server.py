"""The view's web server: viser on one interface (127.0.0.1 unless told), its web client from the installed package."""

from __future__ import annotations

import contextlib
import io
import socket
from typing import Any

import viser

from orc_rpl.errors import UsageError

#: Where the view listens unless `--host` says otherwise: this machine only.
DEFAULT_HOST = "127.0.0.1"
DEFAULT_PORT = 8080


def check_port(port: int | None) -> None:
    """`--port`: a port number (0: the system chooses one)."""
    if port is not None and not 0 <= port <= 65535:
        raise UsageError(f"--port: expected a port number 0..65535, got {port}")


def _no_share_links(*_: Any, **__: Any) -> None:
    """Share links go through a relay on the internet: the view never opens one, whatever a browser asks."""
    return None


def open_server(host: str = DEFAULT_HOST, port: int = DEFAULT_PORT, label: str = "orc view") -> viser.ViserServer:
    """A running viser server bound to `host` (the next free port from `port`), with z up and no share button."""
    _check_host(host)
    with contextlib.redirect_stdout(io.StringIO()):  # viser prints a banner; standard output is the program's
        server = viser.ViserServer(host=host, port=port, label=label, verbose=False)
    # The web client has a share button that asks the server for a public relay link: refuse it.
    server.request_share_url = _no_share_links  # type: ignore[method-assign]
    server.gui.configure_theme(show_share_button=False, dark_mode=False)
    return server


def close_server(server: viser.ViserServer) -> None:
    """Stop the server (its goodbye line stays off standard output)."""
    with contextlib.redirect_stdout(io.StringIO()):
        server.stop()


def _check_host(host: str) -> None:
    """viser tries port after port when it cannot bind, forever for an address this machine does not have."""
    try:
        family = socket.getaddrinfo(host, None)[0][0]
        with socket.socket(family, socket.SOCK_STREAM) as probe:
            probe.bind((host, 0))
    except (OSError, UnicodeError) as error:
        raise UsageError(f"--host {host}: cannot listen on that address ({error})") from None


def url_of(server: viser.ViserServer) -> str:
    """The address a browser opens."""
    host = server.get_host()
    shown = f"[{host}]" if ":" in host else host
    return f"http://{shown}:{server.get_port()}"
