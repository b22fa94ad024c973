"""--plant elastic-gears: the realistic plant with elastic gears under the state feedback, asked for; rigid by default."""

from __future__ import annotations

import io
from pathlib import Path
from typing import Any

import pytest

from orc_rpl.cli import main
from orc_rpl.errors import UsageError
from orc_rpl.executive.cell_robot import CellRobot
from orc_rpl.motion import make_virtual_motion_layer

PROGRAM = 'PRINT "ready"\n'


def _elastic_under_state_feedback(layer: Any) -> bool:
    loop = layer.backend.loop
    return bool(loop.cell.elastic) and loop.state_feedback is not None and loop.twist is not None


def test_the_default_realistic_plant_keeps_rigid_gears() -> None:
    layer = CellRobot.virtual().layer
    assert not _elastic_under_state_feedback(layer) and not layer.backend.loop.cell.elastic
    assert layer.smoothing_s == ()


def test_elastic_gears_are_the_realistic_plant_with_the_gears_whole_servo() -> None:
    layer = make_virtual_motion_layer("irb2400", plant="elastic-gears")
    assert _elastic_under_state_feedback(layer)
    assert layer.gear_friction is not None and layer.path_velocity_control  # the rest of the realistic plant
    assert layer.smoothing_s != ()   # the gears' feed-forward averages moves from rest


@pytest.mark.parametrize("robot", ["ur5e", "so101"])
def test_a_robot_without_a_gear_stiffness_has_no_elastic_gears(robot: str) -> None:
    with pytest.raises(UsageError, match=f"robot '{robot}' has no elastic gears .*irb2400"):
        make_virtual_motion_layer(robot, plant="elastic-gears")


@pytest.fixture
def made(monkeypatch: pytest.MonkeyPatch) -> list[CellRobot]:
    """The simulated robots the command makes."""
    robots: list[CellRobot] = []
    virtual = CellRobot.virtual.__func__  # type: ignore[attr-defined]

    def noted(cls: type[CellRobot], *args: Any, **kwargs: Any) -> CellRobot:
        robots.append(virtual(cls, *args, **kwargs))
        return robots[-1]

    monkeypatch.setattr(CellRobot, "virtual", classmethod(noted))
    return robots


@pytest.mark.sim
def test_orc_run_plant_elastic_gears_reaches_the_plant(tmp_path: Path, made: list[CellRobot],
                                                       capsys: pytest.CaptureFixture[str]) -> None:
    program = tmp_path / "ready.rpl"
    program.write_text(PROGRAM, encoding="utf-8")
    for plant, elastic in (("elastic-gears", True), (None, False)):
        assert main(["run", str(program), *(("--plant", plant) if plant else ())]) == 0
        assert capsys.readouterr().out == "ready\n"
        assert _elastic_under_state_feedback(made[-1].layer) is elastic


@pytest.mark.sim
def test_orc_pendant_plant_elastic_gears_reaches_the_plant(tmp_path: Path, made: list[CellRobot],
                                                           monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "cell.rpl").write_text(PROGRAM, encoding="utf-8")
    monkeypatch.setattr("sys.stdin", io.StringIO(""))
    assert main(["pendant", "cell.rpl", "--plant", "elastic-gears"]) == 0
    assert _elastic_under_state_feedback(made[-1].layer)


@pytest.mark.parametrize("command", ["run", "pendant"])
@pytest.mark.parametrize("robot", ["ur5e", "so101"])
def test_plant_elastic_gears_on_a_robot_without_them_is_a_usage_error(
        command: str, robot: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
        capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "cell.rpl").write_text(PROGRAM, encoding="utf-8")
    monkeypatch.setattr("sys.stdin", io.StringIO(""))
    assert main([command, "cell.rpl", "--robot", robot, "--plant", "elastic-gears"]) == 2
    err = capsys.readouterr().err
    assert (f"--plant elastic-gears: robot '{robot}' has no elastic gears (robots with elastic gears: irb2400)" in err
            and len(err.strip().splitlines()) == 1 and "Traceback" not in err)


@pytest.mark.parametrize("command", ["run", "pendant"])
def test_orc_run_and_orc_pendant_offer_the_same_three_plants(command: str, capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exit_:
        main([command, "--help"])
    assert exit_.value.code == 0
    assert "--plant {realistic,elastic-gears,ideal}" in " ".join(capsys.readouterr().out.split())
