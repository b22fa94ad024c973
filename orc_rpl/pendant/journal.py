"""The autosave journal: every edit appended as one fsync'd JSON line; a killed pendant is recovered from it."""

from __future__ import annotations

import hashlib
import json
import os
import time
from dataclasses import dataclass
from pathlib import Path

from orc_rpl.errors import OrcError


class JournalError(OrcError):
    """The journal cannot be written: the edit is made, but a crash before :save would lose it."""


def journal_path(program_path: str | Path) -> Path:
    """Where a program's journal is: `cell.rpl` -> `.cell.rpl.journal` beside it (hidden, so `orc run *.rpl` never
    picks it up), or, where that cannot be written (a read-only folder, a folder of that name), in the user's
    state folder (`$XDG_STATE_HOME/orc_rpl/journals`, default `~/.local/state/orc_rpl/journals`) under a name
    made from the program's absolute path. Reading and writing ask the same question, so they agree."""
    beside = journal_beside(program_path)
    return beside if _writable(beside) else _journal_in_state_folder(program_path)


def journal_beside(program_path: str | Path) -> Path:
    """The journal's usual place: `.cell.rpl.journal` beside `cell.rpl`."""
    path = Path(program_path)
    return path.with_name(f".{path.name}.journal")


def _journal_in_state_folder(program_path: str | Path) -> Path:
    path = Path(program_path)
    state = Path(os.environ.get("XDG_STATE_HOME") or Path.home() / ".local" / "state")
    digest = hashlib.sha256(str(path.resolve()).encode("utf-8")).hexdigest()[:16]
    return state / "orc_rpl" / "journals" / f"{path.name}.{digest}.journal"


def _writable(journal: Path) -> bool:
    """A journal can be appended at this path (an existing regular file we may write, or a new one in a writable folder)."""
    if journal.exists() or journal.is_symlink():
        return journal.is_file() and os.access(journal, os.W_OK)
    folder = journal.parent if str(journal.parent) else Path(".")
    return folder.is_dir() and os.access(folder, os.W_OK | os.X_OK)


@dataclass(frozen=True, slots=True)
class Entry:
    """One journal record: the program text after an edit and what the edit was."""

    seq: int
    action: str          #: "teach pos1b", "insert move", "delete", ... (shown when offering recovery)
    text: str            #: the whole program after the edit (programs are small; replay is then trivial)
    time_s: float


class Journal:
    """Append-only and fsync'd before an edit is reported done, so SIGKILL at any moment loses nothing.

    The whole program is written with each record: recovery replays the records in order and keeps the
    last complete one; a record torn by the kill (a partial last line) is ignored.
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self._seq = 0
        self._handle: int | None = None

    def append(self, action: str, text: str) -> None:
        """Record an edit durably (the data and, for a new file, its directory entry)."""
        self._seq += 1
        record = json.dumps({"seq": self._seq, "action": action, "text": text, "time": time.time()}) + "\n"
        try:
            created = self._handle is None and not self.path.exists()
            if self._handle is None:
                self.path.parent.mkdir(parents=True, exist_ok=True)  # the state folder, on first use
                self._handle = os.open(self.path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
            os.write(self._handle, record.encode("utf-8"))
            os.fsync(self._handle)
        except OSError as error:
            raise JournalError(f"{action}: done, but the journal {self.path} cannot be written "
                               f"({error.strerror or error}): :save now, or the edit is lost if the pendant is killed") from None
        if created:
            _fsync_directory(self.path.parent)

    def clear(self) -> None:
        """The program was saved: the journal has nothing left to recover."""
        self.close()
        try:
            self.path.unlink()
        except FileNotFoundError:
            pass
        self._seq = 0

    def close(self) -> None:
        if self._handle is not None:
            os.close(self._handle)
            self._handle = None


def read_journal(path: str | Path) -> list[Entry]:
    """The complete records of a journal, in order (none if there is no journal)."""
    try:
        data = Path(path).read_bytes().decode("utf-8", errors="replace")
    except FileNotFoundError:
        return []
    except OSError as error:
        raise JournalError(f"cannot read the journal {path}: {error.strerror or error}") from None
    entries = []
    for line in data.split("\n"):
        try:
            record = json.loads(line)
            entries.append(Entry(int(record["seq"]), str(record["action"]), str(record["text"]), float(record["time"])))
        except (ValueError, KeyError, TypeError):
            continue  # a line torn by a kill, or noise: skip it
    return entries


def recoverable(program_path: str | Path, saved_text: str | None) -> list[Entry]:
    """The journal's records when its last program differs from the saved file (otherwise nothing to recover)."""
    entries = read_journal(journal_path(program_path))
    if not entries:  # a journal left where the folder could not be written then, and can now (or the reverse)
        other = ({journal_beside(program_path), _journal_in_state_folder(program_path)} - {journal_path(program_path)}).pop()
        program = Path(program_path)
        newer = other.is_file() and (not program.exists() or other.stat().st_mtime >= program.stat().st_mtime)
        entries = read_journal(other) if newer else []  # an older one was overtaken by a later :save
    if not entries or entries[-1].text == saved_text:
        return []
    return entries


def _fsync_directory(directory: Path) -> None:
    try:
        fd = os.open(directory, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)
