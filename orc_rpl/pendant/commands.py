"""The pendant's `:` commands: a table of usage and help, argument parsing with errors naming command and argument."""

from __future__ import annotations

import difflib
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from orc_rpl.errors import OrcError

if TYPE_CHECKING:
    from orc_rpl.pendant.session import PendantSession


class CommandError(OrcError):
    """A `:` command typed wrongly; the message names the command and the argument."""


@dataclass(frozen=True, slots=True)
class Command:
    """One pendant command: how it is written, what it does, and what runs it."""

    name: str
    usage: str
    doc: str
    handler: Callable[[PendantSession, list[str], str], str]
    min_args: int = 0
    max_args: int | None = 0


@dataclass(frozen=True, slots=True)
class Outcome:
    """What a line typed at the command line did: the text to show, and whether the pendant should close."""

    text: str
    quit: bool = False
    error: bool = False


def _percent(command: str, text: str) -> float:
    try:
        return float(text[:-1]) / 100.0 if text.endswith("%") else float(text) / 100.0
    except ValueError:
        raise CommandError(f":{command}: expected a percentage such as 50%, got {text!r}") from None


def _line(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise CommandError(f":goto: expected a line number, got {text!r}") from None


def _jog(s: PendantSession, args: list[str], rest: str) -> str:
    if args[0] == "frame":
        if len(args) != 4:
            raise CommandError(":jog frame: expected :jog frame NAME AXIS AMOUNT, e.g. :jog frame base_plate y +1mm")
        return s.jogger.jog("frame", args[2], args[3], frame=args[1])
    if len(args) != 3:
        raise CommandError(f":jog {args[0]}: expected :jog {args[0]} AXIS AMOUNT, e.g. :jog world x +10mm")
    return s.jogger.jog(args[0], args[1], args[2])


def _insert(s: PendantSession, args: list[str], rest: str) -> str:
    if args and args[0] == "move" and len(args) <= 2 and (len(args) == 1 or not args[1][0].isupper()):
        return s.insert_move(args[1] if len(args) == 2 else None)
    if not rest.strip():
        raise CommandError(":insert: expected `move [NAME]` or a statement, e.g. :insert WAIT 0.5s")
    return s.editor.insert(rest)


def _wrap(s: PendantSession, args: list[str], rest: str) -> str:
    name = args[-1]
    if len(args) == 2 and args[0] != "FRAME":
        raise CommandError(f":wrap: expected :wrap FRAME NAME, got {rest!r}")
    return s.editor.wrap(name)


def _io(s: PendantSession, args: list[str], rest: str) -> str:
    if not args:
        return s.panels.io()
    if len(args) != 2:
        raise CommandError(":io: expected :io, or :io CHANNEL VALUE such as :io DigIn[3] 1")
    return s.panels.set_io(args[0], args[1])


def _save(s: PendantSession, args: list[str], rest: str) -> str:
    return s.editor.save(args[0] if args else None)


def _table() -> dict[str, Command]:
    c = [
        Command("jog", "jog SPACE AXIS AMOUNT", "jog: joint 3 +5deg | world x +10mm | tool z -2mm | frame NAME y +1mm",
                _jog, 3, 4),
        Command("override", "override PERCENT", "speed override for programs and jogging, e.g. 50%",
                lambda s, a, r: s.execution.set_override(_percent("override", a[0])), 1, 1),
        Command("mode", "mode manual|auto", "manual caps the TCP speed at 250 mm/s for every motion",
                lambda s, a, r: s.execution.set_mode(a[0]), 1, 1),
        Command("tool", "tool NAME", "the TOOL used by jogging, :teach and :insert move (ARM: the flange)",
                lambda s, a, r: s.execution.set_tool(a[0]), 1, 1),
        Command("teach", "teach NAME", "declare a position at the current pose, relative to the cursor's FRAME block",
                lambda s, a, r: s.teach(a[0]), 1, 1),
        Command("insert", "insert move [NAME] | insert STATEMENT",
                "teach and insert MOVE <tool> TO <it> after the cursor; or insert any statement", _insert, 1, None),
        Command("modpos", "modpos NAME", "touch up a position to the current pose (the original is kept)",
                lambda s, a, r: s.modpos(a[0]), 1, 1),
        Command("positions", "positions", "every position, its frame, value and original", lambda s, a, r: s.panels.positions()),
        Command("undo", "undo [NAME]", "take back the last edit; with NAME, restore a touched-up position",
                lambda s, a, r: s.editor.undo(a[0] if a else None), 0, 1),
        Command("goto", "goto LINE", "cursor to a line", lambda s, a, r: s.editor.goto(_line(a[0])), 1, 1),
        Command("select", "select", "start or clear a selection at the cursor", lambda s, a, r: s.editor.select()),
        Command("delete", "delete", "delete the statement at the cursor (or the selection)", lambda s, a, r: s.editor.delete()),
        Command("replace", "replace STATEMENT", "edit in place: the cursor's statement becomes STATEMENT",
                lambda s, a, r: s.editor.replace(r), 1, None),
        Command("edit", "edit", "put the cursor's statement on the command line to edit it (Enter replaces it)",
                lambda s, a, r: "edit the statement, then Enter"),
        Command("wrap", "wrap FRAME NAME", "wrap the selection in FRAME NAME ... ENDFRAME", _wrap, 1, 2),
        Command("shift", "shift up|down", "move the statement (or the selection) up or down in its block",
                lambda s, a, r: s.editor.shift(a[0]), 1, 1),
        Command("check", "check", "run the checker on the program", lambda s, a, r: s.panels.check()),
        Command("run", "run", "run from the program pointer", lambda s, a, r: s.execution.run()),
        Command("stop", "stop", "stop the robot on its path", lambda s, a, r: s.execution.stop()),
        Command("step", "step", "run one statement at the program pointer", lambda s, a, r: s.execution.step()),
        Command("back", "back", "the previous motion in reverse; the pointer back to its statement", lambda s, a, r: s.pointer.back()),
        Command("pp", "pp", "program pointer to the cursor, with a slow approach to the statement's start",
                lambda s, a, r: s.pointer.pp()),
        Command("exec", "exec", "execute the statement under the cursor in its FRAME block and scope",
                lambda s, a, r: s.execution.exec_cursor()),
        Command("io", "io [CHANNEL VALUE]", "inputs and outputs; set one in simulation", _io, 0, 2),
        Command("log", "log", "the event log", lambda s, a, r: s.panels.log_text()),
        Command("where", "where", "joints, TCP in the cursor's frame, tool, mode", lambda s, a, r: s.panels.where()),
        Command("help", "help [WORD]", "help on a command, a statement or a registered primitive",
                lambda s, a, r: s.panels.help(a[0] if a else None), 0, 1),
        Command("snapshot", "snapshot FILE.png", "an offscreen picture of the cell (MuJoCo)",
                lambda s, a, r: s.panels.snapshot(a[0]), 1, 1),
        Command("save", "save [FILE]", "write the program (atomically); the journal is then cleared", _save, 0, 1),
        Command("recover", "recover", "take the unsaved edits of a killed session from the journal",
                lambda s, a, r: s.editor.recover()),
        Command("quit", "quit | quit!", "leave the pendant; :quit! leaves with unsaved edits (the journal keeps them)",
                lambda s, a, r: "bye"),
    ]
    return {command.name: command for command in c}


COMMANDS: dict[str, Command] = _table()


def run_line(session: PendantSession, line: str) -> Outcome:
    """Carry out one line typed at the command line: a `:` command, or an RPL statement executed at once."""
    outcome = _run_line(session, line)
    session.refresh_view()
    return outcome


def _run_line(session: PendantSession, line: str) -> Outcome:
    text = line.strip()
    if not text:
        return Outcome("")
    try:
        if not text.startswith(":"):
            return Outcome(session.execution.execute_text(line.strip("\n")))
        return _command(session, text[1:])
    except OrcError as error:
        return Outcome(str(error), error=True)


def _command(session: PendantSession, text: str) -> Outcome:
    name, _, rest = text.partition(" ")
    if name in ("quit!", "q!"):
        return Outcome("bye", quit=True)
    if name in ("quit", "q"):
        if session.editor.modified:
            return Outcome("unsaved edits (the journal keeps them): :save first, or :quit! to leave anyway", error=True)
        return Outcome("bye", quit=True)
    command = COMMANDS.get(name)
    if command is None:
        guess = difflib.get_close_matches(name, list(COMMANDS), n=1)
        hint = f"; did you mean :{guess[0]}?" if guess else ""
        raise CommandError(f"unknown command :{name}{hint} (:help lists the commands)")
    args = rest.split()
    if len(args) < command.min_args or (command.max_args is not None and len(args) > command.max_args):
        raise CommandError(f":{name}: wrong number of arguments; usage: :{command.usage}")
    return Outcome(command.handler(session, args, rest))
