"""`orc lsp` over a real JSON-RPC stdio pipe: an editor opens files, types, completes, hovers, jumps and formats."""

from __future__ import annotations

import asyncio
import shutil
from pathlib import Path
from typing import Any, Awaitable, Callable

import pytest
from lsprotocol import types as T
from pygls.uris import from_fs_path

from orc_rpl.cli import main
from tests.lsp.client import Editor

ROOT = Path(__file__).resolve().parents[2]

PROGRAM = """\
TOOL grinder = POSE(0, 0, 150mm, 0, 90deg, 0)
FRAME plate = POSE(1000mm, 0, 500mm, 0, 0, 0)
POS p1 = POSE(100mm, 50mm, 20mm, 0, 180deg, 0) IN plate
CONST Vmax = 1.5mps
PROC Go(q)
  MOVE grinder TO q WITH SPEED = 0.5*Vmax
ENDPROC
FRAME plate
  MOVE grinder TO p1
ENDFRAME
"""


def in_editor(test: Callable[[Editor], Awaitable[Any]]) -> Any:
    """Run `test` against a fresh `python -m orc_rpl lsp` subprocess, shut down properly afterwards."""
    async def session() -> Any:
        async with Editor() as editor:
            return await test(editor)
    return asyncio.run(session())


def where(diagnostic: T.Diagnostic) -> tuple[int, int, int, int]:
    r = diagnostic.range
    return r.start.line, r.start.character, r.end.line, r.end.character


def test_an_unknown_attribute_is_a_diagnostic_on_the_attribute_name(tmp_path: Path) -> None:
    path = tmp_path / "prog.rpl"
    path.write_text(PROGRAM.replace("WITH SPEED", "WITH SPED"))

    async def test(editor: Editor) -> list[T.Diagnostic]:
        return (await editor.open(path))[1]

    [diagnostic] = in_editor(test)
    assert where(diagnostic) == (5, 25, 5, 29)  # `SPED` on line 6, 0-based
    assert "MOVE does not accept attribute 'SPED'; did you mean 'SPEED'?" in diagnostic.message
    assert diagnostic.severity == T.DiagnosticSeverity.Error and diagnostic.source == "orc"


def test_every_error_is_published_as_the_user_types_and_cleared_when_fixed(tmp_path: Path) -> None:
    path = tmp_path / "prog.rpl"
    path.write_text(PROGRAM)

    async def test(editor: Editor) -> tuple[list[T.Diagnostic], ...]:
        uri, clean = await editor.open(path)
        two = await editor.change(uri, PROGRAM.replace("TO p1", "TO p2").replace("TO q", "TO r"))
        typing = await editor.change(uri, PROGRAM + "MOVE grinder TO\n")
        fixed = await editor.change(uri, PROGRAM)
        return clean, two, typing, fixed

    clean, two, typing, fixed = in_editor(test)
    assert clean == [] and fixed == []
    assert [(where(d), d.message.splitlines()[0]) for d in two] == [
        ((5, 18, 5, 19), "undefined name 'r'"),
        ((8, 18, 8, 20), "undefined name 'p2'"),
    ]
    assert len(typing) == 1 and typing[0].range.start.line == 10


def test_an_offline_program_is_checked_against_the_world_its_world_line_names(tmp_path: Path) -> None:
    shutil.copy(ROOT / "worlds" / "cell_thesis.yaml", tmp_path / "cell.yaml")
    path = tmp_path / "prog.orl"
    path.write_text("# world: cell.yaml\nmoveto pos0\nmoveto base_plate.pos3\n")

    async def test(editor: Editor) -> list[T.Diagnostic]:
        return (await editor.open(path))[1]

    [diagnostic] = in_editor(test)
    assert where(diagnostic) == (2, 18, 2, 22)
    assert diagnostic.message.startswith("'base_plate' has no frame, path or attribute 'pos3'")


def test_completion_after_with_lists_the_attributes_of_the_motion_keyword_with_units(tmp_path: Path) -> None:
    path = tmp_path / "prog.rpl"
    text = PROGRAM + "GRINDMOVE grinder TO p1 WITH \nMOVE grinder TO p1\n  WITH \n"
    path.write_text(text)

    async def test(editor: Editor) -> tuple[list[T.CompletionItem], list[T.CompletionItem]]:
        uri, _ = await editor.open(path)
        return await editor.completion(uri, 10, 29), await editor.completion(uri, 12, 7)

    grind, continuation = in_editor(test)
    by_label = {item.label: item for item in grind}
    assert {"SPEED", "FORCE", "GRINDING", "ZONE"} <= set(by_label)
    assert by_label["FORCE"].detail.startswith("a force (N)") and "default 30 N" in by_label["FORCE"].detail
    assert by_label["SPEED"].detail.startswith("a velocity (m/s)") and by_label["SPEED"].insert_text == "SPEED = "
    assert "p1" not in by_label  # after WITH only attributes may follow
    assert "SPEED" in {item.label for item in continuation} and "GRINDING" not in {item.label for item in continuation}


def test_completion_offers_install_kinds_names_in_scope_and_world_objects(tmp_path: Path) -> None:
    shutil.copy(ROOT / "worlds" / "cell_thesis.yaml", tmp_path / "cell.yaml")
    online, offline = tmp_path / "prog.rpl", tmp_path / "prog.orl"
    online.write_text(PROGRAM + "INSTALL gun AS \n")
    offline.write_text("# world: cell.yaml\nmoveto base_plate.\n")

    async def test(editor: Editor) -> tuple[list[T.CompletionItem], ...]:
        uri, _ = await editor.open(online)
        kinds = await editor.completion(uri, 10, 15)
        names = await editor.completion(uri, 8, 18)
        uri, _ = await editor.open(offline)
        return kinds, names, await editor.completion(uri, 1, 18), await editor.completion(uri, 1, 7)

    kinds, names, frames, objects = in_editor(test)
    assert {"SpotGun", "LaserDistance", "Gripper"} <= {item.label for item in kinds}
    assert {"p1", "plate", "Vmax", "grinder", "Go", "POSE"} <= {item.label for item in names}
    assert {item.label for item in frames} == {"pos1", "pos2"}
    assert {"base_plate", "pos0", "pos3", "table"} <= {item.label for item in objects}


def test_hover_on_a_position_shows_its_declaration_frame_and_value_with_units(tmp_path: Path) -> None:
    path = tmp_path / "prog.rpl"
    path.write_text(PROGRAM)

    async def test(editor: Editor) -> tuple[str | None, str | None]:
        uri, _ = await editor.open(path)
        return await editor.hover(uri, 8, 19), await editor.hover(uri, 5, 30)

    position, attribute = in_editor(test)
    assert position is not None and attribute is not None
    assert "**p1**: position, line 3" in position
    assert "POS p1 = POSE(100mm, 50mm, 20mm, 0, 180deg, 0) IN plate" in position
    assert "relative to `plate`" in position
    assert "= (100.0, 50.0, 20.0) mm, (0.0, 180.0, 0.0) deg in plate" in position
    assert "= (1100.0, 50.0, 520.0) mm, (0.0, 180.0, 0.0) deg in world" in position
    assert attribute.startswith("**SPEED**: a velocity (m/s)")


def test_go_to_definition_finds_declarations_and_world_entries(tmp_path: Path) -> None:
    shutil.copy(ROOT / "worlds" / "cell_thesis.yaml", tmp_path / "cell.yaml")
    online, offline = tmp_path / "prog.rpl", tmp_path / "prog.orl"
    online.write_text(PROGRAM + "Go(p1)\n")
    offline.write_text("# world: cell.yaml\nmoveto base_plate.pos1\n")

    async def test(editor: Editor) -> tuple[Any, ...]:
        uri, _ = await editor.open(online)
        routine = await editor.definition(uri, 10, 0)
        position = await editor.definition(uri, 10, 4)
        parameter = await editor.definition(uri, 5, 18)
        uri, _ = await editor.open(offline)
        return routine, position, parameter, await editor.definition(uri, 1, 19)

    routine, position, parameter, world_frame = in_editor(test)
    uri = from_fs_path(str(online))
    assert (routine.uri, routine.range.start.line, routine.range.start.character) == (uri, 4, 5)
    assert (position.uri, position.range.start.line, position.range.start.character) == (uri, 2, 4)
    assert (parameter.range.start.line, parameter.range.start.character) == (4, 8)
    lines = (tmp_path / "cell.yaml").read_text().splitlines()
    assert world_frame.uri == from_fs_path(str(tmp_path / "cell.yaml"))
    assert lines[world_frame.range.start.line].strip().startswith("pos1:")


def test_document_symbols_list_routines_frames_and_positions(tmp_path: Path) -> None:
    path = tmp_path / "prog.rpl"
    path.write_text(PROGRAM)

    async def test(editor: Editor) -> Any:
        uri, _ = await editor.open(path)
        return await editor.symbols(uri)

    symbols = in_editor(test)
    assert [(s.name, s.kind) for s in symbols] == [
        ("grinder", T.SymbolKind.Object), ("plate", T.SymbolKind.Namespace), ("p1", T.SymbolKind.Constant),
        ("Vmax", T.SymbolKind.Constant), ("Go", T.SymbolKind.Function)]
    go = symbols[-1]
    assert (go.range.start.line, go.range.end.line) == (4, 6)


@pytest.mark.parametrize("suffix", [".rpl", ".orl"])
def test_formatting_gives_what_orc_fmt_prints(suffix: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / f"prog{suffix}"
    path.write_text(PROGRAM.replace("  MOVE", "      MOVE") if suffix == ".rpl" else
                    "def Go(q):\n        moveto q  # comment\nGo(HERE)\n")
    assert main(["fmt", str(path)]) == 0
    expected = capsys.readouterr().out

    async def test(editor: Editor) -> list[T.TextEdit] | None:
        uri, _ = await editor.open(path)
        return await editor.formatting(uri)

    [edit] = in_editor(test)
    assert edit.new_text == expected and edit.new_text != path.read_text()
    assert (edit.range.start.line, edit.range.start.character, edit.range.end.line) == (0, 0, len(path.read_text().splitlines()))


def test_an_error_inside_a_request_is_logged_and_the_server_goes_on(tmp_path: Path) -> None:
    path = tmp_path / "prog.rpl"
    path.write_text(PROGRAM)
    missing = from_fs_path(str(tmp_path / "never-opened-and-absent.rpl"))

    async def test(editor: Editor) -> tuple[Any, ...]:
        failed = await editor.hover(missing, 0, 0)  # pygls reads an unopened document from disk: it is not there
        uri, diagnostics = await editor.open(path)
        return failed, diagnostics, await editor.hover(uri, 8, 19), list(editor.logs)

    failed, diagnostics, hover, logs = in_editor(test)
    assert failed is None and diagnostics == [] and hover is not None and "**p1**" in hover
    assert any("orc lsp: hover failed: FileNotFoundError" in line for line in logs)


def test_hover_on_a_world_position_of_an_offline_program_shows_it_as_the_world_file_declares_it(tmp_path: Path) -> None:
    shutil.copy(ROOT / "worlds" / "cell_thesis.yaml", tmp_path / "cell.yaml")
    path = tmp_path / "prog.orl"
    path.write_text("# world: cell.yaml\nmoveto base_plate.pos1\nmoveto pos0\n")

    async def test(editor: Editor) -> tuple[str | None, str | None]:
        uri, _ = await editor.open(path)
        return await editor.hover(uri, 1, 19), await editor.hover(uri, 2, 8)

    frame, obj = in_editor(test)
    assert frame is not None and obj is not None
    assert frame.startswith("**base_plate.pos1**: frame of `base_plate`")
    assert "= (50.0, -40.0, 60.0) mm, (-90.0, 180.0, 0.0) deg relative to `base_plate`" in frame
    assert "= (800.0, -300.0, 900.0) mm, (0.0, 180.0, 0.0) deg relative to `world`" in obj
