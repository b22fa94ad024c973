"""Finding programs to verify and reading the expectation in their header comments."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from orc_rpl.errors import UsageError
from orc_rpl.verify.programs import Expectation, find_programs, read_expectation


@pytest.mark.parametrize("text, expected", [
    ("MOVE t TO p\n", Expectation()),
    ("-- Recover from a bad target.\n-- expect: Unreachable\nMOVE t TO p\n", Expectation("Unreachable", (), 2)),
    ("-- robots: irb2400, ur5e\n\n-- expect: stopped\nSTOP\n", Expectation("stopped", ("irb2400", "ur5e"), 3)),
    ("# world: ../w.yaml\n# expect: failed\nmove a to b\n", Expectation("failed", (), 2)),
    ("MOVE t TO p\n-- expect: Unreachable\n", Expectation()),  # only the header counts, not later comments
], ids=["none", "exception", "robots-and-status", "offline", "after-first-statement"])
def test_header_comments_state_the_expected_outcome(text: str, expected: Expectation) -> None:
    assert read_expectation(Path("p.rpl"), text) == expected


def test_an_expectation_of_two_words_is_refused_with_its_line() -> None:
    with pytest.raises(UsageError, match=r"p.rpl:2: 'expect:' takes one word"):
        read_expectation(Path("p.rpl"), "-- a program\n-- expect: Unreachable or NotFound\n")


def test_process_conditions_are_read_one_a_line() -> None:
    text = "-- expect: welds_good >= 4\n-- expect: parts = Light, Heavy\n# expect: burr_left_mm<0.05\nPRINT 1\n"
    expectation = read_expectation(Path("p.rpl"), text)
    assert expectation.outcome == "finished", "a condition leaves the expected outcome as it was"
    conditions = expectation.process
    assert [(c.name, c.op, c.value, c.line) for c in conditions] == [
        ("welds_good", ">=", 4.0, 1), ("parts", "=", "Light,Heavy", 2), ("burr_left_mm", "<", 0.05, 3)]
    assert conditions[1].failure({"parts": "Light,Heavy"}) is None
    assert conditions[0].failure({"welds_good": 3}) == "expected process welds_good >= 4 (header line 1), got 3"


@pytest.mark.parametrize("line, message", [
    ("-- expect: spatter < 2", r"p.rpl:1: 'expect:' names an unknown process figure 'spatter'; known: welds, "),
    ("-- expect: welds_good =< 4", r"p.rpl:1: 'expect:' with a comparison takes NAME OP VALUE"),
    ("-- expect: welds_good about 4", r"p.rpl:1: 'expect:' takes one word: .* or a condition on a process figure"),
    ("-- expect: parts < cube", r"p.rpl:1: 'expect: parts <' needs a number, got 'cube'"),
])
def test_a_bad_process_condition_is_refused_with_its_line(line: str, message: str) -> None:
    with pytest.raises(UsageError, match=message):
        read_expectation(Path("p.rpl"), line + "\n")


@pytest.mark.parametrize("outcome, status, exception, met", [
    ("finished", "finished", None, True),
    ("finished", "failed", "Unreachable", False),
    ("Unreachable", "failed", "Unreachable", True),
    ("Unreachable", "failed", "JointLimit", False),
    ("Unreachable", "finished", None, False),
    ("failed", "failed", None, True),
    ("rejected", "rejected", None, True),
])
def test_expectation_met(outcome: str, status: str, exception: str | None, met: bool) -> None:
    assert Expectation(outcome).met_by(status, exception) is met


def test_folders_are_searched_in_order_once_each_skipping_hidden_ones(tmp_path: Path,
                                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    for name in ("b/two.orl", "a/one.rpl", ".venv/hidden.rpl", "a/notes.txt"):
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text("-- x\n", encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    found = find_programs([".", "a/one.rpl"])
    assert [f.shown for f in found] == ["a/one.rpl", "b/two.orl"]
    assert found[0].path == (tmp_path / "a/one.rpl").resolve()


def test_a_file_that_is_not_a_program_is_a_usage_error(tmp_path: Path) -> None:
    (tmp_path / "notes.txt").write_text("x", encoding="utf-8")
    with pytest.raises(UsageError, match="is not a program"):
        find_programs([str(tmp_path / "notes.txt")])
    with pytest.raises(UsageError, match="no such file or folder"):
        find_programs([os.fspath(tmp_path / "missing")])
