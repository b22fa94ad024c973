"""The pendant's panels: :positions, :where, :io, :log, :help, :check and :snapshot, as plain text."""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import numpy as np

from orc_rpl.application.declarations import describe_types
from orc_rpl.errors import OrcError
from orc_rpl.executive.signals import RunError
from orc_rpl.pendant.commands import COMMANDS
from orc_rpl.pendant.editing import Editor
from orc_rpl.pendant.events import EventLog
from orc_rpl.pendant.execution import Execution
from orc_rpl.pendant.robot import PendantRobot
from orc_rpl.pendant.tree import EditError
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.lexicon import RESERVED
from orc_rpl.syntax.printer import simple_statement
from orc_rpl.world.pose import Joints, Pose, ShownPose, shown_pose

#: The IO banks the cell has, as the language names them and as the cell does.
IO_BANKS = (("DigIn", "DigIn"), ("DigOut", "DigOut"), ("AnalogIn", "AnaIn"), ("AnalogOut", "AnaOut"))

#: One line on each statement keyword, for :help (the registry documents the application words).
STATEMENT_HELP = {
    "FRAME": "FRAME name ... ENDFRAME: every motion inside is relative to the on-line frame `name`; "
             "FRAME name = POSE(...) [IN parent] declares one",
    "POS": "POS name = POSE(x, y, z, a, b, c) [IN frame] | JOINTS(...): a position (:teach declares one)",
    "TOOL": "TOOL name = POSE(...): a TCP relative to the flange (:tool NAME jogs and teaches with it)",
    "IF": "IF cond THEN ... ELSIF cond THEN ... ELSE ... ENDIF",
    "WHILE": "WHILE cond DO ... ENDWHILE",
    "FOR": "FOR i FROM a TO b [STEP c] DO ... ENDFOR",
    "CASE": "CASE x OF label : ... ELSE : ... ENDCASE",
    "TRY": "TRY ... ON name : ... ENDTRY",
    "PROC": "PROC name(params) ... ENDPROC",
    "FUNC": "FUNC name(params) ... RETURN value ... ENDFUNC",
    "WAIT": "WAIT 0.5s | WAIT UNTIL cond [TIMEOUT 3s]",
    "PRINT": "PRINT a, b: values on one line",
    "INSTALL": "INSTALL name AS Kind WITH ATTR = value: equipment or a sensor",
}


def _format_value(value: object) -> str:
    if type(value) is Pose:
        return shown_pose(value, 2, 2).text() + (f" IN {value.frame}" if value.frame != "world" else "")
    if type(value) is Joints:
        return "JOINTS(" + ", ".join(f"{math.degrees(v):.2f}deg" for v in value.values) + ")"
    return "(no value: its declaration failed)" if value is None else str(value)


class Panels:
    """What the pendant shows besides the program: read-outs of the editor, the execution and the robot."""

    def __init__(self, editor: Editor, execution: Execution, robot: PendantRobot, registry: Any, events: EventLog) -> None:
        self.editor = editor
        self.execution = execution
        self.robot = robot
        self.registry = registry
        self.events = events

    def positions(self) -> str:
        """Every POS with its frame and value; a touched-up one with its original."""
        values = self.execution.executive().machine.globals
        lines = []
        for node in self.editor.program.walk():
            if isinstance(node, n.Declaration) and node.kind == "POS":
                name = node.name.id
                line = f"{name:<14} line {node.span.line:<4} {_format_value(values.get(name))}"
                if name in self.editor.originals:
                    line += f"\n{'':<14} original:  {self.editor.originals[name]}   (:undo {name} restores it)"
                lines.append(line)
        return "\n".join(lines) if lines else "no positions declared (:teach NAME declares one)"

    def where(self) -> str:
        state = self.where_values()
        pose: ShownPose = state["tcp"]
        joints = "  ".join(f"J{i + 1} {q:8.2f}" for i, q in enumerate(state["joints_deg"]))
        return (f"joints (deg)  {joints}\n"
                f"TCP of {state['tool']} in {state['frame']}: {pose.text()}\n"
                f"mode {state['mode']}  override {state['override'] * 100:g}%  time {state['time_s']:.3f} s")

    def io(self) -> str:
        lines = []
        for language, cell in IO_BANKS:
            bank = self.robot.io.bank(cell)
            values = list(bank)
            shown = " ".join(f"{i + 1}:{int(v) if isinstance(v, bool) else f'{v:g}'}" for i, v in enumerate(values))
            lines.append(f"{language:<10} {shown}")
        if getattr(self.robot.layer.backend, "real_arm", False):
            return "\n".join(lines) + "\n(:io DigIn[3] 1 sets a channel: the program's own, this arm has no IO hardware)"
        return "\n".join(lines) + "\n(:io DigIn[3] 1 sets a channel of the simulated cell)"

    def set_io(self, channel: str, value: str) -> str:
        """Set a simulated input or an output: `DigIn[3] 1`, `AnalogIn[1] 2.5`."""
        match = re.fullmatch(r"(DigIn|DigOut|AnalogIn|AnalogOut)\[(\d+)\]", channel)
        if match is None:
            raise EditError(f":io: expected a channel such as DigIn[3] or AnalogOut[1], got {channel!r}")
        bank = self.robot.io.bank(dict(IO_BANKS)[match.group(1)])
        try:
            number = float(value)
            bank[int(match.group(2))] = bool(number) if match.group(1).startswith("Dig") else number
        except ValueError:
            raise EditError(f":io {channel}: expected a number, got {value!r}") from None
        except (IndexError, OrcError) as error:
            raise EditError(f":io {channel}: {error}") from None
        return self.events.record(f"{channel} = {value}")

    def log_text(self, last: int = 200) -> str:
        return "\n".join(self.events.lines[-last:]) or "(no events yet)"

    def check(self) -> str:
        problems = self.editor.check_diagnostics()
        if not problems:
            return "check: no errors"
        return "\n".join(p.format(self.editor.text) for p in problems) + f"\ncheck: {len(problems)} error(s)"

    def snapshot(self, file: str) -> str:
        if not file.endswith(".png"):
            raise EditError(f":snapshot {file}: the picture is written as PNG; name it FILE.png")
        if not Path(file).resolve().parent.is_dir():
            raise EditError(f":snapshot {file}: the folder does not exist")
        try:
            written = self.robot.snapshot(file)
        except OrcError as error:
            raise EditError(f":snapshot: {error}") from None
        return self.events.record(f"snapshot written to {written}")

    def help(self, word: str | None = None) -> str:
        """Help on a pendant command, a statement keyword or any registered primitive, from its declaration."""
        commands = COMMANDS
        if not word:
            usages = [f":{c.usage}" for c in commands.values()]
            half = (len(usages) + 1) // 2
            rows = [f"  {left:<44}{right}" for left, right in zip(usages[:half], usages[half:] + [""])]
            return ("type an RPL statement to execute it at once, or a command (:help WORD explains one, "
                    "and any statement keyword or registered primitive):\n" + "\n".join(rows))
        word = word.lstrip(":").rstrip("!")  # :help quit! explains :quit
        if word in commands:
            c = commands[word]
            return f":{c.usage}\n  {c.doc}"
        reg = self.registry
        if word in reg.motions:
            spec = reg.motions[word]
            lines = [f"{word} tool {' | '.join(t + ' ...' for t in spec.targets)}  ({spec.origin})", f"  {spec.doc}"]
            for a in spec.attributes:
                names = "/".join(a.names)
                default = f" (default {a.default})" if a.default is not None else ""
                lines.append(f"  WITH {names} = {describe_types(a.types)}{default}: {a.doc}")
            return "\n".join(lines)
        if word in reg.functions:
            spec = reg.functions[word]
            params = ", ".join(p.name if p.required else f"{p.name}={p.default}" for p in spec.params)
            return f"{word}({params}{', ...' if spec.variadic else ''})  ({spec.origin})\n  {spec.doc}"
        if word in reg.install_kinds:
            spec = reg.install_kinds[word]
            lines = [f"INSTALL name AS {word}  ({spec.origin})", f"  {spec.doc}"]
            lines += [f"  WITH {a.name} = {describe_types(a.types)}: {a.doc}" for a in spec.attributes]
            lines += [f"  .{m.name}: {m.doc}" for m in spec.methods]
            return "\n".join(lines)
        if word in STATEMENT_HELP:
            return STATEMENT_HELP[word]
        declared = self.editor.declared().get(word)
        if declared is not None:
            first = simple_statement(declared) if not isinstance(declared, n.Routine) else f"{declared.kind} {word}"
            return f"{word}: declared at line {declared.span.line}: {first}"
        if word in RESERVED:
            return f"{word}: a reserved word of RPL (docs/language.md)"
        raise EditError(f":help: nothing is called {word!r} (:help lists the commands)")

    def where_values(self) -> dict[str, Any]:
        """Joints (deg), TCP (relative to the cursor's frame, as shown to people), tool, mode, override: the state panel's numbers."""
        frame = self.editor.context()[1]
        execution = self.execution
        try:
            ex = execution.executive()
            world = self.robot.tcp_pose(execution.tool_pose())
            pose = Pose.from_matrix(np.linalg.inv(ex.machine.frame_matrix(frame)) @ world.matrix(), frame)
        except (RunError, OrcError):
            pose, frame = self.robot.tcp_pose(None), "world"
        joints = tuple(round(q, 2) + 0.0 for q in self.robot.joints_deg())  # shown to 0.01 deg: never -0.00
        return {"joints_deg": joints, "tcp": shown_pose(pose, 2, 2), "frame": frame, "tool": execution.tool,
                "mode": execution.mode, "override": execution.override, "time_s": self.robot.time_s()}
