"""Finding the programs to verify and reading what their header comments expect of them."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

from orc_rpl.errors import UsageError
from orc_rpl.verify.outcomes import Condition, parse_condition

SUFFIXES = (".rpl", ".orl")

#: Statuses a program may be expected to end in; any other word is the name of the exception it must fail with.
STATUSES = ("finished", "stopped", "failed", "rejected")

#: `-- expect: Unreachable` (on-line) or `# robots: irb2400, ur5e` (off-line) among the leading comment lines, and
#: `-- expect: welds_good = 4` (a condition on the process outcomes, one a line).
_HEADER = re.compile(r"^(?:--|#)\s*(expect|robots)\s*:\s*(.*?)\s*$")
_OPERATOR = re.compile(r"[=<>!]")
_WORD = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


@dataclass(frozen=True, slots=True)
class Expectation:
    """What a program's header says about its run: how it ends and on which robots it runs."""

    outcome: str = "finished"             #: a status of STATUSES, or the name of the exception it fails with
    robots: tuple[str, ...] = ()          #: the robots it runs on; empty: any robot
    line: int = 0                         #: the header line of `expect:` (0: not stated)
    process: tuple[Condition, ...] = ()   #: conditions on the process outcomes (verify.outcomes)

    def met_by(self, status: str, exception: str | None) -> bool:
        """True when a run that ended in `status` (and `exception`, if it failed) is what the header expects."""
        if self.outcome in STATUSES:
            return status == self.outcome
        return status == "failed" and exception == self.outcome


@dataclass(frozen=True, slots=True)
class Found:
    """A program to verify: its path as shown to the user, its absolute path and its expectation."""

    shown: str
    path: Path
    expectation: Expectation


def read_expectation(path: Path, text: str) -> Expectation:
    """The `expect:` and `robots:` lines of the comment block that opens the program (a UsageError naming the line).
    An `expect:` with a comparison (`welds_good = 4`) is a condition on the process figures; one word, the outcome."""
    outcome, robots, where = "finished", (), 0
    process: list[Condition] = []
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if not stripped:
            continue
        if not stripped.startswith(("--", "#")):
            break  # the header ends at the first statement
        match = _HEADER.match(stripped)
        if match is None:
            continue
        key, value = match.groups()
        if key == "expect" and _OPERATOR.search(value):
            try:
                process.append(parse_condition(value, number))
            except ValueError as error:
                raise UsageError(f"{path}:{number}: {error}") from None
        elif key == "expect":
            if not _WORD.match(value):
                raise UsageError(f"{path}:{number}: 'expect:' takes one word: {', '.join(STATUSES)} "
                                 f"or the name of an exception such as Unreachable; or a condition on a process "
                                 f"figure such as welds_good = 4; got {value!r}")
            outcome, where = value, number
        else:
            names = tuple(name.strip() for name in value.split(","))
            if not all(_WORD.match(name) for name in names):
                raise UsageError(f"{path}:{number}: 'robots:' takes robot names separated by commas, got {value!r}")
            robots = names
    return Expectation(outcome, robots, where, tuple(process))


def _shown(path: Path) -> str:
    """The path relative to the current folder when it is inside it (baselines key runs by it)."""
    try:
        return path.relative_to(Path.cwd()).as_posix()
    except ValueError:
        return path.as_posix()


def _walk(folder: Path) -> list[Path]:
    """Program files under a folder, in sorted order, skipping hidden folders (.git, .venv)."""
    found = []
    for path in sorted(folder.rglob("*")):
        relative = path.relative_to(folder).parts
        if any(part.startswith(".") or part == "__pycache__" for part in relative):
            continue
        if path.suffix in SUFFIXES and path.is_file():
            found.append(path)
    return found


def find_programs(paths: Sequence[str]) -> list[Found]:
    """Every `.rpl` and `.orl` file named or found under the folders named, once each, in a stable order."""
    files: list[Path] = []
    for given in paths:
        path = Path(given)
        if path.is_dir():
            files.extend(_walk(path))
        elif path.is_file():
            if path.suffix not in SUFFIXES:
                raise UsageError(f"'{given}' is not a program (expected .rpl or .orl)")
            files.append(path)
        else:
            raise UsageError(f"'{given}': no such file or folder")
    seen: set[Path] = set()
    found = []
    for file in files:
        absolute = file.resolve()
        if absolute in seen:
            continue
        seen.add(absolute)
        try:
            text = absolute.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as error:
            raise UsageError(f"cannot read '{file}': {error}") from None
        found.append(Found(_shown(absolute), absolute, read_expectation(file, text)))
    return found
