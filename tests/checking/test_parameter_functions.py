"""FUNCs the motion layer evaluates (targets, attributes, UNTIL, IDENT): proved pure by `orc check`, run by `orc run`."""

from __future__ import annotations

from pathlib import Path

import pytest

from orc_rpl.cli import main
from orc_rpl.executive.cell_robot import CellRobot
from orc_rpl.executive.executive import Executive
from orc_rpl.executive.machine import Machine
from orc_rpl.syntax.parser import parse

HEAD = """\
VAR count = 0
POS start = POSE(0.8, 0, 0.6, 0, 180deg, 0)
TOOL grinder = POSE(0, 0, 0.1, 0, 0, 0)
FUNC wave(s)
    RETURN OFFS(start, 0.1 * s, 0.02 * SIN(s * 6.2832), 0)
ENDFUNC
"""

IMPURE = [
    ("assigns a global", "FUNC ramp(s)\n    count = count + 1\n    RETURN 20N\nENDFUNC\nGRINDMOVE grinder TO start WITH FORCE = ramp\n",
     "8:5: FUNC ramp is used as attribute FORCE at line 11, so it must be free of side effects, but it assigns the global 'count'"),
    ("writes an output", "FUNC ramp(s)\n    DigOut[2] = 1\n    RETURN 20N\nENDFUNC\nGRINDMOVE grinder TO start WITH FORCE = ramp\n",
     "8:5: FUNC ramp is used as attribute FORCE at line 11, so it must be free of side effects, but it writes the output DigOut"),
    ("prints", "FUNC ramp(s)\n    IF s > 0.5 THEN\n        PRINT s\n    ENDIF\n    RETURN 20N\nENDFUNC\n"
     "GRINDMOVE grinder TO start WITH FORCE = ramp\n",
     "9:9: FUNC ramp is used as attribute FORCE at line 13, so it must be free of side effects, but it prints"),
    ("waits", "FUNC ramp(s)\n    WAIT 1s\n    RETURN 20N\nENDFUNC\nGRINDMOVE grinder TO start WITH FORCE = ramp\n",
     "8:5: FUNC ramp is used as attribute FORCE at line 11, so it must be free of side effects, but it waits"),
    ("moves the robot, as a target", "FUNC path(s)\n    MOVE ARM TO start\n    RETURN start\nENDFUNC\nLMOVE ARM TO path\n",
     "8:5: FUNC path is used as the target at line 11, so it must be free of side effects, but it moves the robot (MOVE)"),
    ("calls a function that moves the robot", "FUNC ramp(s)\n    seam = RecordSeam([start])\n    RETURN 20N\nENDFUNC\n"
     "GRINDMOVE grinder TO start WITH FORCE = ramp\n",
     "8:5: FUNC ramp is used as attribute FORCE at line 11, so it must be free of side effects, but it calls RecordSeam, "
     "which moves the robot"),
    ("through a helper", "FUNC helper(x)\n    count = x\n    RETURN x\nENDFUNC\nFUNC ramp(s)\n    RETURN helper(20N)\nENDFUNC\n"
     "GRINDMOVE grinder TO start WITH FORCE = ramp\n",
     "12:5: FUNC ramp is used as attribute FORCE at line 14, so it must be free of side effects, but it calls helper, "
     "which assigns the global 'count' (line 8)"),
    ("an UNTIL condition", "FUNC seen()\n    DigOut[3] = 1\n    RETURN DigIn[2] = 1\nENDFUNC\nMOVE ARM TO start UNTIL seen()\n",
     "11:25: an UNTIL condition must be free of side effects, but this one calls seen, which writes the output DigOut (line 8)"),
]


@pytest.mark.parametrize("body, expected", [c[1:] for c in IMPURE], ids=[c[0] for c in IMPURE])
def test_orc_check_proves_parameter_functions_pure(body: str, expected: str, tmp_path: Path,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    program = tmp_path / "p.rpl"
    program.write_text(HEAD + body)
    assert main(["check", str(program)]) == 2
    out = capsys.readouterr().out
    assert f"{program}:{expected}\n" in out, out
    assert out.count(f"{program}:") == 1, out


PURE = HEAD + """\
FUNC ramp(s)
    VAR local = 20N       -- locals, globals read, inputs read: all fine
    local = local + 10N * s * (count + 1)
    RETURN local
ENDFUNC
LMOVE ARM TO start
LMOVE ARM TO wave WITH SPEED = 0.1mps
PRINT ROUND(HERE.x / 1mm, 1), ROUND(HERE.y / 1mm, 1)
GRINDMOVE grinder TO OFFS(start, 0, 0, -0.1) WITH FORCE = ramp
"""


def test_a_func_target_checks_and_runs(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    program = tmp_path / "wave.rpl"
    program.write_text(PURE)
    assert main(["check", str(program)]) == 0
    assert main(["run", str(program)]) == 0
    assert capsys.readouterr().out.splitlines()[0] == "900 0"


def test_a_func_target_is_frame_checked(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    program = tmp_path / "wave.rpl"
    program.write_text(HEAD + "FRAME table = POSE(0.8, 0, 0.5, 0, 0, 0)\nFRAME table\n    LMOVE ARM TO wave\nENDFRAME\n")
    assert main(["check", str(program)]) == 2
    out = capsys.readouterr().out
    assert f"{program}:9:18: FUNC wave gives poses relative to world (line 5), but this motion is inside FRAME table" in out


def test_the_planner_calls_a_parameter_function_once_per_grid_point(monkeypatch: pytest.MonkeyPatch) -> None:
    calls: list[tuple[str, tuple[float, ...]]] = []
    original = Machine.call_now

    def counting(self: Machine, routine, args, span):  # type: ignore[no-untyped-def]
        calls.append((routine.name, tuple(float(a) for a in args)))
        return original(self, routine, args, span)

    monkeypatch.setattr(Machine, "call_now", counting)
    executive = Executive(parse(PURE, "wave.rpl"), CellRobot.virtual(), path="wave.rpl", source=PURE, output=lambda line: None)
    executive.run()
    assert executive.status == "finished", executive.report()
    for name in ("wave", "ramp"):
        points = [args for routine, args in calls if routine == name]
        assert points and len(points) == len(set(points)), (name, len(points), len(set(points)))
