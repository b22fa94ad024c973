"""The autosave journal: every edit appended as one fsync'd JSON line; a killed pendant is recovered from it."""

from __future__ import annotations

import json
import os
import time
from dataclasses import dataclass
from pathlib import Path


def journal_path(program_path: str | Path) -> Path:
    """`cell.rpl` -> `.cell.rpl.journal` beside it (hidden, so `orc run *.rpl` never picks it up)."""
    path = Path(program_path)
    return path.with_name(f".{path.name}.journal")


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
        created = self._handle is None and not self.path.exists()
        if self._handle is None:
            self._handle = os.open(self.path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
        os.write(self._handle, record.encode("utf-8"))
        os.fsync(self._handle)
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
