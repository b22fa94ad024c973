"""What the pendant's panes show, as prompt-toolkit formatted text: listing, robot state, messages, function keys."""

from __future__ import annotations

from typing import TYPE_CHECKING

from prompt_toolkit.formatted_text import StyleAndTextTuples
from prompt_toolkit.styles import Style, merge_styles, style_from_pygments_cls
from pygments.styles import get_style_by_name

from orc_rpl.pendant.lexer import RplLexer

if TYPE_CHECKING:
    from orc_rpl.pendant.session import PendantSession

#: The pendant's own colours on top of a Pygments theme for the program text.
STYLE = merge_styles([
    style_from_pygments_cls(get_style_by_name("monokai")),
    Style.from_dict({
        "cursor-line": "reverse",
        "pointer": "fg:ansiyellow bold",
        "selected": "bg:ansiblue",
        "gutter": "fg:ansibrightblack",
        "title": "bold fg:ansicyan",
        "label": "fg:ansibrightblack",
        "value": "bold",
        "manual": "fg:ansiyellow bold",
        "error": "fg:ansired bold",
        "fkey": "reverse",
        "fkey-number": "bold fg:ansicyan",
        "busy": "fg:ansigreen bold",
    }),
])

_LEXER = RplLexer()


def _highlight(line: str) -> StyleAndTextTuples:
    """One line of program text as Pygments tokens, styled by the Pygments theme."""
    out: StyleAndTextTuples = []
    for token, text in _LEXER.get_tokens(line):
        if text == "\n":
            continue
        out.append(("class:pygments." + ".".join(token).lower() if token else "", text))
    return out


def listing(session: PendantSession, height: int) -> StyleAndTextTuples:
    """The program with line numbers, the program pointer (>) and the cursor (reversed line), scrolled to the cursor."""
    editor = session.editor
    lines = editor.text.split("\n")[:-1] if editor.text else []
    cursor = editor.cursor_line
    pointer = session.execution.pointer_line
    selected: set[int] = set()
    if editor.mark is not None and editor.stops:
        a, b = sorted((editor.stops[editor.mark].line, cursor))
        selected = set(range(a, b + 1))
    first = max(1, min(cursor - height // 2, len(lines) - height + 1))
    out: StyleAndTextTuples = [("class:title", f" {editor.path.name}{' *' if editor.modified else ''}\n")]
    for number in range(first, min(len(lines), first + height - 1) + 1):
        mark = ">" if number == pointer else " "
        out.append(("class:pointer" if mark == ">" else "class:gutter", f"{mark}{number:4} "))
        style = "class:cursor-line " if number == cursor else "class:selected " if number in selected else ""
        for token_style, text in _highlight(lines[number - 1]) or [("", " ")]:
            out.append((style + token_style, text))
        out.append(("", "\n"))
    if not lines:
        out.append(("class:label", "  (empty program: type a statement, :insert one, or :insert move)\n"))
    return out


def state(session: PendantSession) -> StyleAndTextTuples:
    """Robot state: joints, TCP in the cursor's frame, tool, mode, override, jog settings, what is running."""
    values = session.panels.where_values()
    pose = values["tcp"]
    out: StyleAndTextTuples = [("class:title", " Robot\n")]
    for i, q in enumerate(values["joints_deg"]):
        out += [("class:label", f"  J{i + 1} "), ("class:value", f"{q:9.2f} deg\n")]
    out.append(("class:label", f" TCP of {values['tool']} in {values['frame']}\n"))
    for axis, value in zip("xyz", (pose.x_mm, pose.y_mm, pose.z_mm)):
        out += [("class:label", f"  {axis} "), ("class:value", f"{value:9.2f} mm\n")]
    for axis, value in zip("abc", (pose.a_deg, pose.b_deg, pose.c_deg)):
        out += [("class:label", f"  {axis} "), ("class:value", f"{value:9.2f} deg\n")]
    mode_style = "class:manual" if values["mode"] == "manual" else "class:value"
    out += [("class:label", " mode "), (mode_style, values["mode"]),
            ("class:label", "  override "), ("class:value", f"{values['override'] * 100:g}%\n"),
            ("class:label", " jog "), ("class:value", f"{session.jogger.space_label()} {session.jogger.axis_label()}\n"),
            ("class:label", "     "), ("class:value", f"{session.jogger.increment_label()}\n"),
            ("class:label", f" t = {values['time_s']:.2f} s\n")]
    if session.execution.busy:
        out.append(("class:busy", f" {session.execution.job_name} running\n"))
    return out


def messages(text: str, error: bool) -> StyleAndTextTuples:
    return [("class:error" if error else "", text)]


def function_bar(labels: list[str], mode: str) -> StyleAndTextTuples:
    """The bottom bar: F1..F8 with their meaning in the current mode, as on an industrial pendant."""
    out: StyleAndTextTuples = [("class:title", f"[{mode}] ")]
    for i, label in enumerate(labels):
        out += [("class:fkey-number", f"F{i + 1}"), ("class:fkey", f"{label:<8}"), ("", " ")]
    return out
