"""Completion at the command line: pendant commands, RPL keywords, registered motion keywords and their attributes, names."""

from __future__ import annotations

import re
from collections.abc import Iterable
from typing import TYPE_CHECKING

from prompt_toolkit.completion import CompleteEvent, Completer, Completion
from prompt_toolkit.document import Document

from orc_rpl.pendant.commands import COMMANDS
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.lexicon import PREDEFINED_NAMES, RESERVED

if TYPE_CHECKING:
    from orc_rpl.pendant.session import PendantSession

_WORD = re.compile(r"[A-Za-z_][A-Za-z0-9_]*$")
_MOTION_START = re.compile(r"^\s*([A-Z][A-Z0-9_]*MOVE|MOVE)\b")
#: What the arguments of some commands can be.
_ARGUMENTS = {"mode": ("manual", "auto"), "shift": ("up", "down"), "jog": ("joint", "world", "tool", "frame")}


def _names(session: PendantSession, kinds: tuple[str, ...] | None = None) -> list[str]:
    out = []
    for name, node in session.editor.declared().items():
        if kinds is None or (isinstance(node, n.Declaration) and node.kind in kinds):
            out.append(name)
    return out


def candidates(session: PendantSession, before_cursor: str) -> tuple[str, list[str]]:
    """The word being typed and the words that complete it, for the text before the cursor on the current line."""
    match = _WORD.search(before_cursor)
    word = match.group(0) if match else ""
    head = before_cursor[: len(before_cursor) - len(word)]
    stripped = head.lstrip()
    if stripped.startswith(":"):
        if stripped == ":":
            return word, sorted(c for c in COMMANDS if c.startswith(word))
        command = stripped[1:].split()[0] if stripped[1:].split() else ""
        if command in ("teach", "modpos", "undo"):
            pool = _names(session, ("POS",)) if command != "teach" else []
        elif command == "tool":
            pool = ["ARM", *_names(session, ("TOOL",))]
        elif command == "wrap":
            pool = ["FRAME", *_names(session, ("FRAME",))]
        elif command == "jog" and stripped.split()[-1] == "frame":
            pool = _names(session, ("FRAME",))
        elif command == "help":
            pool = [*COMMANDS, *session.registry.words(), *RESERVED]
        elif command == "insert":
            pool = ["move", *_rpl_words(session)]
        else:
            pool = list(_ARGUMENTS.get(command, ()))
        return word, sorted({p for p in pool if p.startswith(word)})
    motion = _MOTION_START.match(before_cursor)
    if motion is not None and re.search(r"\bWITH\s+$", head):
        spec = session.registry.motions.get(motion.group(1))
        if spec is not None:
            return word, sorted(a for a in spec.attribute_names if a.startswith(word))
    if not word:
        return word, []
    return word, sorted({w for w in _rpl_words(session) if w.startswith(word) and w != word})


def _rpl_words(session: PendantSession) -> Iterable[str]:
    registry = session.registry
    yield from RESERVED
    yield from registry.motions
    yield from registry.functions
    yield from PREDEFINED_NAMES
    yield from session.editor.declared()


class RplCompleter(Completer):
    """prompt-toolkit's view of `candidates`."""

    def __init__(self, session: PendantSession) -> None:
        self.session = session

    def get_completions(self, document: Document, complete_event: CompleteEvent) -> Iterable[Completion]:
        word, words = candidates(self.session, document.current_line_before_cursor)
        for candidate in words:
            yield Completion(candidate, start_position=-len(word))
