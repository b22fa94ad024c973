"""Start `orc bus emulate` in its own process (the SDKs busy-poll: an emulator thread would starve)."""

from __future__ import annotations

import contextlib
import subprocess
import sys
from collections.abc import Iterator


@contextlib.contextmanager
def emulated_bus(*options: str) -> Iterator[str]:
    """The pseudo-terminal path of an emulated SO-101 (options as on the command line)."""
    process = subprocess.Popen([sys.executable, "-m", "orc_rpl", "bus", "emulate", *options],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        path = process.stdout.readline().strip()
        if not path.startswith("/dev/"):
            raise RuntimeError(f"the emulator did not start: {path!r} {process.stderr.read()}")
        yield path
    finally:
        process.terminate()
        process.wait(timeout=10)
