"""Equipment ports: which `PORT` strings name a device a program may open, and nothing else.

pyserial's `serial_for_url` understands URL schemes that reach files (`spy://...?file=`) and the
network (`socket://`, `rfc2217://`); a robot program must reach neither. A port is "sim", a serial
device, or the in-memory loopback `loop://` (the emulator the tests use); anything else is refused
by the checker at the attribute's string literal and, for computed strings, at run time.
"""

from __future__ import annotations

import os
import re
import stat

#: The simulated device of the cell.
SIMULATED = "sim"

#: The in-memory loopback of pyserial: echoes what is written, touches no file and no network.
LOOPBACK = "loop://"

#: Devices by name: a device file directly in /dev (ttyUSB0, ttyACM0, cu.usbserial, rfcomm0), a pseudo-terminal,
#: the stable /dev/serial/by-id and by-path links, Windows COM ports. No URL scheme, no other folder.
_DEVICE = re.compile(r"(/dev/[A-Za-z0-9_][A-Za-z0-9_.:+-]*|/dev/pts/\d+|/dev/serial/by-(?:id|path)/[A-Za-z0-9_.:+-]+|COM\d{1,3})")

#: Device files in /dev that are never equipment: memory, randomness, sinks, and the console.
_NOT_EQUIPMENT = frozenset({"null", "zero", "full", "random", "urandom", "mem", "kmem", "port", "console", "tty",
                            "stdin", "stdout", "stderr", "ptmx", "fd", "shm", "kmsg"})


def port_problem(port: str) -> str | None:
    """Why `port` is not a port a program may name (a message), or None when it is one."""
    if port in (SIMULATED, LOOPBACK):
        return None
    if _DEVICE.fullmatch(port) and not (port.startswith("/dev/") and port[5:] in _NOT_EQUIPMENT):
        return None
    return (f"'{port}' is not an equipment port: use \"sim\", a serial device such as \"/dev/ttyUSB0\", "
            "\"/dev/serial/by-id/...\" or \"COM3\", or \"loop://\"")


def device_problem(port: str) -> str | None:
    """Why an existing `/dev` path cannot be opened as equipment (it is not a character device), or None."""
    if not port.startswith("/dev/"):
        return None
    try:
        mode = os.stat(port).st_mode
    except OSError:
        return None  # a missing device: opening it says so
    return None if stat.S_ISCHR(mode) else f"'{port}' is not a serial device (not a character device)"


def is_device(port: str) -> bool:
    """True for a real serial device (not "sim" and not the in-memory loopback)."""
    return port not in (SIMULATED, LOOPBACK) and port_problem(port) is None
