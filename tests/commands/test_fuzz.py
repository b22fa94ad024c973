"""Generated hostile inputs through the real command lines: programs, worlds, sidecars, options and pendant lines
always end in a located error or a result with exit 0, 1 or 2, never a traceback or an internal error.

The default run tries a few dozen seeds of each; `pytest -m slow` runs the long versions."""

from __future__ import annotations

import random
import shutil
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from orc_rpl.cli import main
from tests import fuzz_inputs

ROOT = Path(__file__).resolve().parents[2]
SEEDS = st.integers(0, 2**32 - 1)
QUICK = settings(max_examples=25, deadline=None, suppress_health_check=list(HealthCheck))
LONG = settings(max_examples=400, deadline=None, suppress_health_check=list(HealthCheck))


class Cell:
    """A scratch copy of worlds/ with program folders beside it, as the repository lays them out."""

    def __init__(self) -> None:
        self.root = Path(tempfile.mkdtemp(prefix="orc-fuzz-"))
        shutil.copytree(ROOT / "worlds", self.root / "worlds")
        for folder in ("online", "offline"):
            (self.root / "programs" / folder).mkdir(parents=True)
        shutil.copy(ROOT / "programs" / "offline" / "spot_welding.orl", self.root / "programs" / "offline")

    def program(self, suffix: str, text: str) -> Path:
        folder = "offline" if suffix == ".orl" else "online"
        path = self.root / "programs" / folder / f"gen{suffix}"
        path.write_text(text, encoding="utf-8")
        return path


@pytest.fixture(scope="module")
def cell() -> Cell:
    made = Cell()
    yield made
    shutil.rmtree(made.root, ignore_errors=True)


def orc(capsys: pytest.CaptureFixture[str], argv: list[str]) -> int:
    try:
        code = main(argv)
    except SystemExit as exit_:  # argparse's usage errors
        code = exit_.code  # type: ignore[assignment]
    captured = capsys.readouterr()
    text = captured.out + captured.err
    assert "Traceback" not in text and "internal error" not in text, (argv, text[-2000:])
    assert code in (0, 1, 2), (argv, code, text[-2000:])
    return int(code)


def _programs(cell: Cell, capsys: pytest.CaptureFixture[str], seed: int) -> None:
    suffix, text = fuzz_inputs.program(random.Random(seed))
    path = cell.program(suffix, text)
    assert orc(capsys, ["check", str(path)]) in (0, 2)
    orc(capsys, ["fmt", str(path)])


def _worlds(cell: Cell, capsys: pytest.CaptureFixture[str], seed: int) -> None:
    world = cell.root / "worlds" / "gen.yaml"
    world.write_text(fuzz_inputs.world(random.Random(seed)), encoding="utf-8")
    program = cell.root / "programs" / "offline" / "spot_welding.orl"
    assert orc(capsys, ["check", str(program), "--world", str(world)]) in (0, 2)


def _sidecars(cell: Cell, capsys: pytest.CaptureFixture[str], seed: int) -> None:
    program = cell.program(".rpl", "PRINT 1\n")
    program.with_suffix(".sim.yaml").write_text(fuzz_inputs.sidecar(random.Random(seed)), encoding="utf-8")
    orc(capsys, ["run", str(program)])


@QUICK
@given(SEEDS)
def test_generated_programs_get_located_errors(cell, capsys, seed) -> None:
    _programs(cell, capsys, seed)


@QUICK
@given(SEEDS)
def test_generated_worlds_get_located_errors(cell, capsys, seed) -> None:
    _worlds(cell, capsys, seed)


@QUICK
@given(SEEDS)
def test_generated_sidecars_get_usage_errors_naming_them(cell, capsys, seed) -> None:
    _sidecars(cell, capsys, seed)


@pytest.mark.parametrize("line", fuzz_inputs.OPTION_LINES, ids=lambda line: " ".join(line) or "(none)")
def test_hostile_option_lines_are_usage_errors(cell, capsys, line) -> None:
    program = cell.program(".rpl", "PRINT 1\n")
    argv = [part.format(p=program, d=cell.root, o=cell.root / "out") for part in line]
    orc(capsys, argv)
    assert program.read_text() == "PRINT 1\n"


def _pendant_lines(tmp_path: Path, seed: int, count: int) -> None:
    from orc_rpl.pendant.commands import run_line
    from tests.pendant.support import session_on

    rng = random.Random(seed)
    session = session_on(tmp_path)
    for _ in range(count):
        outcome = run_line(session, fuzz_inputs.pendant_line(rng))
        assert "internal error" not in outcome.text and "Traceback" not in outcome.text


def test_generated_pendant_lines_get_answers(tmp_path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    _pendant_lines(tmp_path, 9, 60)


@pytest.mark.slow
@pytest.mark.parametrize("job", [_programs, _worlds, _sidecars], ids=["programs", "worlds", "sidecars"])
def test_many_generated_inputs(cell, capsys, job) -> None:
    @LONG
    @given(SEEDS)
    def many(seed: int) -> None:
        job(cell, capsys, seed)
    many()


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(10))
def test_many_generated_pendant_lines(tmp_path, monkeypatch, seed) -> None:
    monkeypatch.chdir(tmp_path)
    _pendant_lines(tmp_path, seed, 200)
