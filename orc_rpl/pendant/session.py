"""The pendant's headless session: the parts (editor, execution, jogger, program pointer, panels) joined over one robot."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from orc_rpl.application.standard_behaviour import runtime_registry
from orc_rpl.pendant.editing import Editor, PendantError
from orc_rpl.pendant.events import EventLog
from orc_rpl.pendant.execution import Execution
from orc_rpl.pendant.jogging import Jogger
from orc_rpl.pendant.journal import Journal, journal_beside, journal_path
from orc_rpl.pendant.panels import Panels
from orc_rpl.pendant.pointer import ProgramPointer
from orc_rpl.pendant.robot import PendantRobot
from orc_rpl.pendant.viewing import View, ViewLink
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.printer import simple_statement
from orc_rpl.world.pose import Joints

__all__ = ["PendantError", "PendantSession"]

#: The largest program file the pendant opens (a robot program is a few thousand lines).
MAX_PROGRAM_BYTES = 10_000_000


class PendantSession:
    """One pendant, nothing here knows about the terminal: each part owns its state, the session wires them.

    `editor` (the program, cursor, undo, journal, saving), `execution` (the executive, tool, override, mode
    and the running job), `jogger` (jog settings and jog moves), `pointer` (:pp and :back), `panels`
    (read-outs) and, with a 3D view, `view` (keeps it in step). What needs two parts at once, teaching, lives here. Every command returns the text to show.
    The session starts in manual mode (every motion capped at 250 mm/s at the TCP), as an industrial
    pendant does.
    """

    def __init__(self, path: str | Path | None = None, text: str | None = None, robot: PendantRobot | None = None,
                 registry: object = None, journal: bool = True, synchronous: bool = True,
                 on_print: Callable[[str], None] | None = None, mode: str = "manual") -> None:
        file = Path(path) if path is not None else Path("untitled.rpl")
        self.registry = registry or runtime_registry()
        self.robot = robot or PendantRobot.virtual()
        self.events = EventLog(self.robot.time_s)
        saved_text = _read_program(file) if file.exists() else None
        if text is None:
            text = saved_text if saved_text is not None else ""
        self.editor = Editor(file, text, saved_text, Journal(journal_path(file)) if journal else None,
                             self.registry, self.events)
        self.execution = Execution(self.editor, self.robot, self.registry, self.events, synchronous, on_print, mode)
        self.jogger = Jogger(self.editor, self.execution, self.robot, self.events)
        self.pointer = ProgramPointer(self.editor, self.execution, self.robot, self.events)
        self.panels = Panels(self.editor, self.execution, self.robot, self.registry, self.events)
        self.view: ViewLink | None = None   #: the 3D view, when one is shown (show_in)
        self.events.record(f"opened {file} ({len(text.splitlines())} lines)")
        where = self.editor.journal.path if self.editor.journal is not None else None
        if where is not None and where != journal_beside(file):
            self.events.record(f"the folder of {file} cannot hold its journal: edits are journaled in {where}")

    @classmethod
    def open(cls, path: str | Path, recover: bool = False, **options: object) -> PendantSession:
        """Open a program file; with `recover`, take the program from the autosave journal of a killed session."""
        session = cls(path, **options)  # type: ignore[arg-type]
        if recover:
            session.editor.recover()
        return session

    def show_in(self, view: View, url: str | None = None) -> ViewLink:
        """Keep a 3D view in step with this session from now on (`orc pendant --view`)."""
        self.view = ViewLink(view, self.editor, self.execution, self.robot, self.events, url)
        self.view.refresh()
        return self.view

    def refresh_view(self) -> None:
        """After a command, and while the screen idles: the view shows the program and the selection as they are."""
        if self.view is not None:
            self.view.refresh()

    def close(self) -> None:
        if self.view is not None:
            self.view.close()
            self.view = None
        self.editor.close()

    # -- teaching: the robot's pose (execution) written into the program (editor) ------------------

    def teach(self, name: str, action: str | None = None) -> str:
        """Declare a position at the current pose, relative to the FRAME block containing the cursor."""
        editor = self.editor
        name = editor.new_name(name)
        frame = editor.context()[1]
        declaration = editor.declare_position(name, self.execution.current_pose_text(frame), frame,
                                              action or f"teach {name}")
        where = f"relative to FRAME {frame}" if frame != "world" else "relative to world (the cursor is outside every FRAME block)"
        return self.events.record(f"taught {simple_statement(declaration)}  -- {where}")

    def insert_move(self, name: str | None = None) -> str:
        """Teach a position and insert `MOVE <tool> TO <it>` after the cursor's statement, inside the right block."""
        editor, tool = self.editor, self.execution.tool
        name = editor.new_name(name) if name else editor.free_name()
        frame = editor.context()[1]
        had_statements = bool(editor.stops)
        declaration = editor.insert_move(name, self.execution.current_pose_text(frame), frame, tool)
        if had_statements:
            self.events.record(f"taught {simple_statement(declaration)}")
        return self.events.record(f"inserted MOVE {tool} TO {name} at line {editor.cursor_line}"
                                  + (f", inside FRAME {frame}" if frame != "world" else ""))

    def modpos(self, name: str) -> str:
        """Touch up a position: its numbers become the current pose, in the frame it is declared relative to."""
        editor, execution = self.editor, self.execution
        declaration, _ = editor.position(name)
        frame = declaration.frame.id if declaration.frame is not None else "world"
        value = execution.executive().machine.globals.get(name)
        joints = type(value) is Joints or (isinstance(declaration.value, n.Call)
                                           and getattr(declaration.value.function, "id", "") == "JOINTS")
        text = execution.current_joints_text() if joints else execution.current_pose_text(frame)
        new = editor.touch_up(name, text)
        return self.events.record(f"modpos {simple_statement(new)}  (original kept: {editor.originals[name]})")


def _read_program(path: Path) -> str:
    """The program file's text; a PendantError naming the file when it cannot be read as text."""
    if not path.is_file():  # a FIFO or a device would block or never end
        raise PendantError(f"cannot open {path}: not a regular file")
    if path.stat().st_size > MAX_PROGRAM_BYTES:
        raise PendantError(f"cannot open {path}: {path.stat().st_size} bytes is more than a program "
                           f"({MAX_PROGRAM_BYTES // 1_000_000} MB at most)")
    try:
        return path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise PendantError(f"cannot open {path}: it is not a UTF-8 text file") from None
    except OSError as error:
        raise PendantError(f"cannot open {path}: {error.strerror or error}") from None
