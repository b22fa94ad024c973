"""Start `orc bus emulate` in its own process (the SDKs busy-poll: an emulator thread would starve)."""

from __future__ import annotations

import contextlib
import subprocess
import sys
from collections.abc import Iterator


def _wait_until_it_answers(path: str, options: tuple[str, ...]) -> None:
    """A busy machine may take a while to schedule a freshly started process: wait for its first answer."""
    from orc_rpl.hardware.bus import ServoBus
    from orc_rpl.hardware.emulator import codec_for

    bus = ServoBus(path, codec_for("dynamixel" if "dynamixel" in options else "feetech"))
    try:
        for _ in range(50):
            if bus.ping(1) is not None:
                return
    finally:
        bus.close()


@contextlib.contextmanager
def emulated_bus(*options: str) -> Iterator[str]:
    """The pseudo-terminal path of an emulated SO-101 (options as on the command line)."""
    process = subprocess.Popen([sys.executable, "-m", "orc_rpl", "bus", "emulate", *options],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        path = process.stdout.readline().strip()
        if not path.startswith("/dev/"):
            raise RuntimeError(f"the emulator did not start: {path!r} {process.stderr.read()}")
        _wait_until_it_answers(path, options)
        yield path
    finally:
        process.terminate()
        process.wait(timeout=10)
