"""`orc run --set NAME=VALUE` replaces a top-level CONST; bad names and values are usage errors before anything moves."""

from __future__ import annotations

from pathlib import Path

import pytest

from orc_rpl.cli import main

PROGRAM = "-- a parameter\nCONST n = 3\nCONST gap = 10mm\nPRINT n * 2\nPRINT gap + 1mm\n"


def orc(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def program(tmp_path: Path) -> str:
    path = tmp_path / "param.rpl"
    path.write_text(PROGRAM, encoding="utf-8")
    return str(path)


def test_set_replaces_the_values_of_consts(program: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert orc(capsys, "run", program)[1].splitlines() == ["6", "0.011 m"]
    code, out, err = orc(capsys, "run", program, "--set", "n=5", "--set", "gap=24mm")
    assert code == 0, err
    assert out.splitlines() == ["10", "0.025 m"]


@pytest.mark.parametrize("setting, message", [
    ("m=5", "--set m=5: the program has no top-level CONST 'm' (its CONSTs: gap, n)"),
    ("n", "--set: expected NAME=VALUE"),
    ("n=((", "'((' is not a value of the language"),
])
def test_bad_settings_are_usage_errors(program: str, setting: str, message: str,
                                       capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = orc(capsys, "run", program, "--set", setting)
    assert code == 2 and out == ""
    assert message in err


def test_a_value_of_the_wrong_dimension_is_a_check_error_where_it_is_used(program: str,
                                                                          capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = orc(capsys, "run", program, "--set", "gap=2s")
    assert code == 2 and out == ""
    assert "param.rpl:5:" in err and "nothing moved" in err
