"""What the view draws without a browser: the planned-path signal, a still view of a world and a program's positions."""

from __future__ import annotations

import numpy as np
import pytest

from tests.view.support import ROOT

pytest.importorskip("viser", reason="the 3D view is the [view] extra")

from orc_rpl.application.standard_behaviour import runtime_registry  # noqa: E402
from orc_rpl.motion import JointMotion, make_virtual_motion_layer  # noqa: E402
from orc_rpl.transform.loading import load_program  # noqa: E402
from orc_rpl.view.server import close_server, open_server  # noqa: E402
from orc_rpl.view.still import show_still  # noqa: E402
from orc_rpl.world import load_world  # noqa: E402


def test_motion_layer_signals_the_planned_path_before_the_move_starts() -> None:
    layer = make_virtual_motion_layer(backend="kinematic")
    heard: list[tuple[int, np.ndarray, int]] = []
    target = tuple(np.asarray(layer.current_q()) + 0.2)
    layer.plan_listeners.add(lambda move_id, tcp_m: heard.append((move_id, tcp_m, layer.cycles)))
    handle = layer.move(JointMotion(target_rad=target))
    assert len(heard) == 1 and heard[0][0] == handle.id
    _, tcp_m, cycles = heard[0]
    assert cycles == 0, "heard before the first motion cycle"
    assert tcp_m.ndim == 2 and tcp_m.shape[1] == 3 and len(tcp_m) >= 2
    np.testing.assert_allclose(tcp_m[0], layer.fk(layer.current_q())[:3, 3], atol=1e-9)
    np.testing.assert_allclose(tcp_m[-1], layer.fk(np.array(target))[:3, 3], atol=1e-9)


@pytest.mark.sim
def test_still_view_shows_the_world_and_the_programs_positions_once() -> None:
    world_path = ROOT / "worlds" / "cell_thesis.yaml"
    world = load_world(world_path)
    _, program = load_program(ROOT / "programs" / "offline" / "thesis_7_3.orl", world_path)
    server = open_server(port=0)
    try:
        view = show_still(server, world, program, runtime_registry(), "irb2400", "cell_thesis")
    finally:
        close_server(server)
    scene = view.scene
    assert {"table", "fixture", "base_plate", "pos0", "pos3", "grinder"} <= set(scene.objects)
    # the world's named frames; the program's own POS declarations of the same places are not drawn twice
    assert set(scene.positions) == {"base_plate.pos1", "base_plate.pos2"}
    pos1 = world.world_pose("base_plate.pos1")
    np.testing.assert_allclose(scene.positions["base_plate.pos1"].position, (pos1.x, pos1.y, pos1.z), atol=1e-9)
    # the robot's links are there, at home
    assert len(scene.moving) >= 6
    assert scene.paths == {}


def test_highlight_enlarges_one_position_and_colours_one_planned_path() -> None:
    from orc_rpl.view.scene import HIGHLIGHT_RGB, HIGHLIGHT_SCALE, PATH_RGB, CellScene

    server = open_server(port=0)
    try:
        scene = CellScene(server)
        scene.set_position("p1", np.eye(4))
        scene.set_position("p2", np.eye(4))
        scene.add_path(1, np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.2, 0.0, 0.0]]))
        scene.add_path(2, np.array([[0.2, 0.0, 0.0], [0.2, 0.1, 0.0]]))
        scene.highlight(position="p2", move_id=1)
        assert (scene.positions["p1"].scale, scene.positions["p2"].scale) == (1.0, HIGHLIGHT_SCALE)
        assert (scene.paths[1].colors == HIGHLIGHT_RGB).all() and (scene.paths[2].colors == PATH_RGB).all()
        scene.highlight()
        assert scene.positions["p2"].scale == 1.0 and (scene.paths[1].colors == PATH_RGB).all()
    finally:
        close_server(server)


def test_the_newest_planned_paths_stay_on_screen_the_oldest_node_showing_the_next() -> None:
    from orc_rpl.view.scene import HIGHLIGHT_RGB, PATH_RGB, PATHS_KEPT, CellScene

    server = open_server(port=0)
    try:
        scene = CellScene(server)
        for move_id in range(1, PATHS_KEPT + 1):
            scene.add_path(move_id, np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.01 * move_id]]))
        first_nodes = {id(node) for node in scene.paths.values()}
        scene.highlight(move_id=1)
        longer = np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.1, 0.2, 0.0]])
        scene.add_path(PATHS_KEPT + 1, longer)
        assert sorted(scene.paths) == list(range(2, PATHS_KEPT + 2)), "the oldest path is gone, the newest shown"
        assert {id(node) for node in scene.paths.values()} == first_nodes, "no node made: the oldest one's reused"
        newest = scene.paths[PATHS_KEPT + 1]
        np.testing.assert_allclose(newest.points, np.stack([longer[:-1], longer[1:]], axis=1), atol=1e-6)
        assert (newest.colors == PATH_RGB).all() and newest.thickness == 3.0, "not highlighted as its node was"
        assert not any((node.colors == HIGHLIGHT_RGB).all() for node in scene.paths.values())
        scene.add_path(5, longer[::-1])  # a move planned anew is drawn in its own node again
        assert len(scene.paths) == PATHS_KEPT and list(scene.paths)[-1] == 5
        np.testing.assert_allclose(scene.paths[5].points[0, 0], longer[-1], atol=1e-6)
    finally:
        close_server(server)


@pytest.mark.sim
@pytest.mark.parametrize("program", sorted([*(ROOT / "programs").glob("*/*.rpl"), *(ROOT / "programs").glob("*/*.orl")]),
                         ids=lambda p: p.name)
def test_every_program_of_the_repository_shows_its_positions_without_running(program) -> None:
    from orc_rpl.syntax.files import declared_world

    world_path = declared_world(program, program.read_text(encoding="utf-8")) or ROOT / "worlds" / "cell_thesis.yaml"
    _, tree = load_program(program, world_path)
    server = open_server(port=0)
    try:
        view = show_still(server, load_world(world_path), tree, runtime_registry(), "irb2400", program.name, str(program))
    finally:
        close_server(server)
    assert view.scene.positions, "a program of the repository declares or uses positions"
    assert view.executive.status == "finished"
