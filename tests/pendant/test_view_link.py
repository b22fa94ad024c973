"""The pendant's link to a 3D view: the view is fed each motion cycle by the robot, and brought up to date once the
robot stands still, not at every turn of the screen's pump."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from orc_rpl.pendant.commands import run_line
from tests.pendant.support import session_on


class CountingView:
    """A view that counts what the link asks of it."""

    def __init__(self) -> None:
        self.ticks = 0
        self.updates = 0

    def follow(self, executive: Any, program: Any) -> None:
        pass

    def on_tick(self) -> None:
        self.ticks += 1

    def update(self) -> None:
        self.updates += 1

    def highlight(self, position: str | None = None, move_id: int | None = None) -> None:
        pass


def test_a_jog_brings_the_view_up_to_date_once_when_it_ends(tmp_path: Path) -> None:
    session = session_on(tmp_path, synchronous=False)
    view = CountingView()
    session.show_in(view)
    before = view.updates
    outcome = run_line(session, ":jog world z +50mm")
    assert not outcome.error, outcome.text
    execution, robot = session.execution, session.robot
    pumps = 0
    while execution.busy or robot.pending() > 0:  # the screen's pump: a few motion cycles, then a refresh
        execution.pump(5)
        session.refresh_view()
        pumps += 1
    for _ in range(3):  # the screen idles on
        session.refresh_view()
    assert pumps > 3 and view.ticks > 0, "the jog took several pumps, the robot fed the view each cycle"
    assert view.updates - before == 1, "one update, where the robot stopped"
    session.close()
