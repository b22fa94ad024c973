"""What a command may write: outputs checked against its inputs and each other before any work, written as a set.

Every command names its inputs and outputs here once. An output that is one of the inputs (the same
path once resolved, or the same file through another name: same device and inode) or another
output is a usage error (exit 2) before anything is read or computed, so that no run can replace the
program it ran with its summary. The folder of every output must exist and be writable, also
checked up front, so that a long run is not done and then lost.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

from orc_rpl.atomic import discard, prepare_atomic, write_text_atomic
from orc_rpl.errors import UsageError
from orc_rpl.syntax.files import interrupted_mark


def quiet_stdout() -> None:
    """The reader went away (`orc fmt F | head`): drop the rest of the output without a traceback."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):
        pass


def _identity(path: str) -> tuple[str, tuple[int, int] | None]:
    """The resolved path and, when the file exists, its (device, inode)."""
    resolved = os.path.realpath(path)
    try:
        info = os.stat(resolved)
    except OSError:
        return resolved, None
    return resolved, (info.st_dev, info.st_ino)


def same_file(a: str, b: str) -> bool:
    """True when `a` and `b` name one file (resolved path, or device and inode when both exist)."""
    path_a, node_a = _identity(a)
    path_b, node_b = _identity(b)
    return path_a == path_b or (node_a is not None and node_a == node_b)


def check_outputs(inputs: dict[str, str | None], outputs: dict[str, str | None],
                  in_place: tuple[tuple[str, str], ...] = ()) -> None:
    """UsageError when an output is an input or another output, or cannot be written; nothing is touched.

    `inputs` and `outputs` map what the user reads in the message (`FILE`, `--summary-json`) to a path
    (None: not given; "-": standard output). `in_place` lists (input label, output label) pairs that
    are documented in-place updates (`convert --world` updating the world it was given).
    """
    given_inputs = {label: path for label, path in inputs.items() if path not in (None, "-")}
    given_outputs = {label: path for label, path in outputs.items() if path not in (None, "-")}
    seen: dict[str, str] = {}
    for label, path in given_outputs.items():
        assert path is not None
        for input_label, input_path in given_inputs.items():
            assert input_path is not None
            if (input_label, label) not in in_place and same_file(path, input_path):
                raise UsageError(f"{label}: '{path}' is also the input {input_label}; "
                                 "an output never replaces an input, choose another file")
        for other_label, other in seen.items():
            if same_file(path, other):
                raise UsageError(f"{label}: '{path}' is also the output {other_label}; choose another file")
        seen[label] = path
        check_writable(label, path)


def check_writable(label: str, path: str) -> None:
    """UsageError unless `path` can be created or replaced: its folder exists and is writable, and it is no folder,
    device or FIFO."""
    target = Path(path)
    if target.is_dir():
        raise UsageError(f"{label}: '{path}' is a directory")
    if target.exists() and not target.is_file():  # a device or a FIFO: a rename would replace it with a file
        raise UsageError(f"{label}: '{path}' is not a regular file")
    folder = Path(os.path.realpath(target)).parent
    if not folder.is_dir():
        raise UsageError(f"{label}: the folder of '{path}' does not exist")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise UsageError(f"{label}: the folder of '{path}' is not writable")


def write_all_atomic(texts: dict[str, str], program: str | None = None) -> None:
    """Write several files as one set: every temporary first, then the renames; temporaries removed on failure.

    With several files, `interrupted_mark(program)` lists them from before the first rename until after the
    last, so a kill between two renames leaves it behind and the next command that reads the program says so.
    """
    prepared: list[tuple[str, str]] = []
    mark = interrupted_mark(program) if program is not None and len(texts) > 1 else None
    try:
        for path, text in texts.items():
            prepared.append((prepare_atomic(path, text), os.path.realpath(path)))
        if mark is not None:
            write_text_atomic(mark, "".join(f"{path}\n" for path in texts))
    except BaseException:
        for temporary, _ in prepared:
            discard(temporary)
        raise
    renamed = 0
    try:
        for temporary, target in prepared:
            os.replace(temporary, target)
            renamed += 1
    except BaseException:  # Ctrl-C or a failure between renames: the mark stays, the rest is not left lying about
        for temporary, _ in prepared[renamed:]:
            discard(temporary)
        raise
    if mark is not None:
        mark.unlink()

