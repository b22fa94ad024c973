"""A servo bus adapter that goes away in the middle of a run (unplugged USB) is a DriveFault at the statement."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.hardware.emulators import emulated_bus
from tests.hardware.test_run_on_bus import MOVES, orc_run

pytestmark = pytest.mark.sim


def test_a_port_that_goes_away_is_a_drive_fault_naming_the_bus(tmp_path: Path) -> None:
    back_and_forth = MOVES + "WHILE TRUE DO\n    MOVE jaws TO a\n    MOVE jaws TO b\nENDWHILE\n"
    with emulated_bus("--robot", "so101", "--duration-s", "15") as port:  # then its port goes away
        code, _, err, summary = orc_run(tmp_path, back_and_forth, "--port", port)
    assert code == 1, err
    assert summary["error"]["exception"] == "DriveFault", summary["error"]
    # the closed port fails the next read or write, or the servos stop answering first: a drive fault either way
    message = summary["error"]["message"]
    assert "the servo bus: the port " in message or "does not answer on" in message, message
    assert "internal error" not in err
