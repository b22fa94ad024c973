"""The applications' process overlays in the view: weld spots and their quality, the tracked seam, the ground edge."""

from __future__ import annotations

import numpy as np
import pytest

from tests.view.support import ROOT

pytest.importorskip("viser", reason="the 3D view is the [view] extra")

from orc_rpl.application.standard_behaviour import runtime_registry  # noqa: E402
from orc_rpl.executive.cell_robot import CellRobot  # noqa: E402
from orc_rpl.executive.executive import Executive  # noqa: E402
from orc_rpl.executive.sim_io import load_script, script_path  # noqa: E402
from orc_rpl.transform.loading import load_program  # noqa: E402
from orc_rpl.view.process import TRACED, error_colours, process_record  # noqa: E402
from orc_rpl.view.remote import Picture, ViewProcess  # noqa: E402
from orc_rpl.view.scene import BAD_RGB, GOOD_RGB  # noqa: E402
from orc_rpl.view.streamed import StreamedView  # noqa: E402

pytestmark = pytest.mark.sim


def _watch(name: str) -> tuple[Picture, Executive]:
    """Run an on-line demo (its IO script installed) with the view watching; what the view shows after the run."""
    path = ROOT / "programs" / "online" / name
    source, program = load_program(path)
    robot = CellRobot.virtual(plant="ideal")
    executive = Executive(program, robot, runtime_registry(), path=str(path), source=source, output=lambda line: None)
    script = script_path(path)
    if script is not None:
        load_script(script, robot.io, lambda: robot.tcp_pose(executive.machine.last_tool))
    server = ViewProcess("127.0.0.1", 0)  # the server in its own process, as `orc run --view` has it
    try:
        view = StreamedView(server.scene, executive, robot)
        view.attach(program)
        view.monitor(robot)
        assert executive.run() == "finished", executive.report()
        view.finish()
        shown = server.scene.snapshot()
    finally:
        server.close()
    return shown, executive


def test_weld_spots_are_drawn_where_the_gun_closed_with_their_quality() -> None:
    shown, executive = _watch("demo_spot_welding.rpl")
    welds = process_record(executive.machine.robot).welds
    assert len(welds) == 6 and len(shown.welds) == 6
    for number, weld in enumerate(welds, start=1):
        spot = shown.welds[number]
        np.testing.assert_allclose(spot.position, weld.position_m, atol=1e-9)
        assert tuple(spot.color) == (GOOD_RGB if weld.good else BAD_RGB)
    assert "welds 6 good, 0 bad" in shown.caption


def test_the_ground_edge_is_drawn_coloured_by_the_error_along_the_normal() -> None:
    shown, executive = _watch("thesis_3_1_deburring.rpl")
    points, colours = shown.process["normal_error_m"]
    assert len(points) > 50 and len(colours) == len(points)
    # each point is where the TCP was: on the edge the program grinds, between its two ends
    xyz = np.array(points)
    assert np.ptp(xyz[:, 1]) > 0.3, "the trace runs along the edge"
    green = error_colours(np.zeros(1), TRACED["normal_error_m"])[0]
    assert any(tuple(c) != tuple(green) for c in colours), "the bulges show as a rise of the error"
    bulges = process_record(executive.machine.robot).bulges
    last = bulges[-1]
    assert f"bulge {1000 * last.caught_height_m:.2f} mm before, {1000 * last.left_m:.2f} mm after" \
        in shown.caption
