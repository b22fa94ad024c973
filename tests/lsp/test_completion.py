"""What completion offers where, read from the line being typed (no server needed)."""

from __future__ import annotations

import pytest

from orc_rpl.application.registry import default_registry
from orc_rpl.lsp.completion import complete
from orc_rpl.lsp.index import ProgramIndex
from orc_rpl.syntax.parser import parse

REGISTRY = default_registry()
DECLARED = "TOOL gun = POSE(0, 0, 100mm, 0, 0, 0)\nPOS p1 = POSE(1m, 0, 1m, 0, 180deg, 0)\n"
INDEX = ProgramIndex(parse(DECLARED + "PROC Go(q)\n  n = 1\nENDPROC\n", "prog.rpl"))


def labels(lines: list[str], offline: bool = False) -> list[str]:
    """Completion labels with the cursor at the end of the last line."""
    items = complete(lines, len(lines) - 1, len(lines[-1]), REGISTRY, INDEX, None, offline)
    return [item.label for item in items]


@pytest.mark.parametrize("lines, wanted, unwanted", [
    pytest.param(["WELDMOVE gun TO p1 WITH "], {"SPEED", "ZONE"}, {"p1", "MOVE"}, id="after-with-only-attributes"),
    pytest.param(["GRINDMOVE gun TO p1", "  WITH SPEED = 1mps", "  WITH F"], {"FORCE", "GRINDING"}, {"p1"},
                 id="continuation-line-uses-the-motion-above"),
    pytest.param(["INSTALL g AS "], {"SpotGun", "Gripper", "LaserDistance"}, {"p1"}, id="install-kinds"),
    pytest.param(["INSTALL g AS SpotGun WITH "], {"CLOSE", "WELD_OK", "REACTION"}, {"SPEED"}, id="install-attributes"),
    pytest.param(["MOVE gun TO "], {"p1", "gun", "POSE", "HERE"}, {"IF", "SPEED"}, id="names-in-an-expression"),
    pytest.param([""], {"MOVE", "GRINDMOVE", "IF", "PROC", "p1"}, set(), id="statement-start-keywords-and-names"),
    pytest.param(["x = ROBOT."], {"Joints", "Torque"}, {"p1"}, id="robot-software-sensors"),
])
def test_online_completion(lines: list[str], wanted: set[str], unwanted: set[str]) -> None:
    got = set(labels(lines))
    assert wanted <= got and not unwanted & got


def test_locals_and_parameters_are_offered_only_inside_their_routine() -> None:
    inside = complete(["PROC Go(q)", "  n = 1", "  MOVE gun TO "], 2, 16, REGISTRY, INDEX, None, False)
    outside = labels(["MOVE gun TO "])
    assert {"q", "n", "p1"} <= {item.label for item in inside} and not {"q", "n"} & set(outside)


def test_offline_motion_offers_lower_case_attributes_ready_to_take_a_value() -> None:
    items = complete(["grindmove gun along casting.edge "], 0, 33, REGISTRY, INDEX, None, True)
    force = next(item for item in items if item.label == "force")
    assert force.insert_text == "force=" and force.detail.startswith("a force (N)")
    assert "moveto" in labels([""], offline=True) and "MOVE" not in labels([""], offline=True)


def test_a_typed_space_opens_completion_only_where_a_short_list_follows() -> None:
    def after_space(line: str) -> list[str]:
        return [item.label for item in complete([line], 0, len(line), REGISTRY, INDEX, None, False, after_space=True)]

    assert after_space("MOVE gun TO ") == [] and after_space("x = ") == []
    assert "SPEED" in after_space("MOVE gun TO p1 WITH ") and "SpotGun" in after_space("INSTALL g AS ")
