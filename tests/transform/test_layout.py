"""Lossless round trips of any layout: statements the transformation or an edit leaves alone keep their text."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings

from orc_rpl.cli import main
from orc_rpl.syntax.files import declared_world
from orc_rpl.syntax.layout import print_offline_keeping, print_online_keeping
from orc_rpl.syntax.offline_parser import parse_offline
from orc_rpl.syntax.offline_printer import print_offline
from orc_rpl.syntax.parser import parse
from orc_rpl.syntax.printer import print_program
from orc_rpl.transform.pipeline import to_offline, to_online
from orc_rpl.world import World, load_world, loads_world
from tests.transform.helpers import HERE, ROOT
from tests.transform.layout_strategies import layouts

CORPUS = HERE / "layouts"
OFFLINE = sorted(CORPUS.glob("*.orl"))
ONLINE = sorted(CORPUS.glob("*.rpl"))
CELL = ROOT / "worlds" / "cell_thesis.yaml"
SETTINGS = dict(deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


def offline_there_and_back(text: str, world: World, fresh_world: World) -> tuple[str, str]:
    """(on-line text, off-line text back in the layout of `text`)."""
    base = parse_offline(text, "prog.orl")
    online = print_program(to_online(base, world, "prog.orl", text).program)
    back = to_offline(parse(online, "prog.rpl"), fresh_world)
    return online, print_offline_keeping(back.program, text, base)


def online_there_and_back(text: str) -> tuple[str, str]:
    """(off-line text, on-line text back in the layout of `text`), through the world made from its declarations."""
    base = parse(text, "prog.rpl")
    job = to_offline(base, None)
    offline, world_text = print_offline(job.program), job.world.dump()
    again = to_online(parse_offline(offline, "prog.orl"), loads_world(world_text, "made.yaml"))
    return offline, print_online_keeping(again.program, text, base)


def test_the_corpus_is_in_odd_layouts() -> None:
    """The corpus is worth its name: fmt would change every file of it."""
    for path in OFFLINE:
        assert print_offline(parse_offline(path.read_text(encoding="utf-8"))) != path.read_text(encoding="utf-8")
    for path in ONLINE:
        assert print_program(parse(path.read_text(encoding="utf-8"))) != path.read_text(encoding="utf-8")


@pytest.mark.parametrize("path", OFFLINE, ids=lambda p: p.stem)
def test_offline_layout_comes_back_byte_for_byte_both_ways(path: Path) -> None:
    text = path.read_text(encoding="utf-8")
    world_path = declared_world(path, text)
    assert world_path is not None
    online, back = offline_there_and_back(text, load_world(world_path), load_world(world_path))
    assert back == text
    # the other way: the on-line form, in the layout it was written in, comes back from off-line
    base = parse(online, "prog.rpl")
    offline = print_offline(to_offline(base, load_world(world_path)).program)
    again = to_online(parse_offline(offline), load_world(world_path)).program
    assert print_online_keeping(again, online, base) == online


@pytest.mark.parametrize("path", ONLINE, ids=lambda p: p.stem)
def test_online_layout_comes_back_byte_for_byte_both_ways(path: Path) -> None:
    text = path.read_text(encoding="utf-8")
    offline, back = online_there_and_back(text)
    assert back == text


def test_convert_with_base_keeps_every_untouched_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    shutil.copy(CELL, tmp_path / "cell.yaml")
    odd = (CORPUS / "thesis_odd.orl").read_text(encoding="utf-8").replace("../../../worlds/cell_thesis.yaml", "cell.yaml")
    (tmp_path / "prog.orl").write_text(odd)
    assert main(["convert", str(tmp_path / "prog.orl"), "-o", str(tmp_path / "prog.rpl")]) == 0
    online = (tmp_path / "prog.rpl").read_text()
    (tmp_path / "prog.rpl").write_text(online.replace("WAIT 0.1s", "WAIT 0.25s"))  # an edit on-line
    assert main(["convert", str(tmp_path / "prog.rpl"), "--world", str(tmp_path / "cell.yaml"),
                 "--base", str(tmp_path / "prog.orl"), "-o", str(tmp_path / "back.orl")]) == 0
    back = (tmp_path / "back.orl").read_text().splitlines()
    before = odd.splitlines()
    changed = [i for i, (a, b) in enumerate(zip(before, back)) if a != b]
    assert len(back) == len(before) and [before[i] for i in changed] == ["  wait  0.1s"]
    assert back[changed[0]] == "  wait 0.25s"  # canonical, at the indentation of its block
    # without --base: the canonical text, as orc fmt writes it (with the world line convert writes)
    assert main(["convert", str(tmp_path / "prog.rpl"), "--world", str(tmp_path / "cell.yaml")]) == 0
    canonical = print_offline(parse_offline((tmp_path / "back.orl").read_text())).replace("#world:", "# world:")
    assert capsys.readouterr().out == canonical


def test_convert_refuses_a_base_of_the_wrong_representation(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    shutil.copy(CELL, tmp_path / "cell.yaml")
    (tmp_path / "prog.orl").write_text("# world: cell.yaml\nmoveto pos0\n")
    assert main(["convert", str(tmp_path / "prog.orl"), "--base", str(tmp_path / "prog.orl")]) == 2
    assert "--base" in capsys.readouterr().err


def test_an_edit_inside_a_block_keeps_the_rest_of_the_block() -> None:
    text = (CORPUS / "deburring_odd.orl").read_text(encoding="utf-8")
    base = parse_offline(text)
    edited = text.replace("   n=n+1\n", "   n=n+2\n")
    program = parse_offline(edited)
    kept = print_offline_keeping(program, text, base)
    assert kept == text.replace("   n=n+1\n", "   n = n + 2\n")


def test_a_new_statement_in_a_two_space_block_takes_the_blocks_indentation() -> None:
    text = "if n > 1 :   # odd\n  wait  1s\nelse:\n  wait 2s\n"
    base = parse_offline(text)
    program = parse_offline(text.replace("  wait  1s\n", "  wait  1s\n  print(n)\n"))
    assert print_offline_keeping(program, text, base) == "if n > 1 :   # odd\n  wait  1s\n  print(n)\nelse:\n  wait 2s\n"


@settings(max_examples=int(os.environ.get("ORC_LAYOUT_EXAMPLES", "150")), **SETTINGS)
@given(layouts(offline=True))
def test_generated_offline_layouts_come_back_byte_for_byte(text: str) -> None:
    world = load_world(CELL)
    online, back = offline_there_and_back(text, world, load_world(CELL))
    assert back == text
    base = parse(online, "prog.rpl")
    again = to_online(parse_offline(print_offline(to_offline(base, load_world(CELL)).program)), world).program
    assert print_online_keeping(again, online, base) == online


@settings(max_examples=int(os.environ.get("ORC_LAYOUT_EXAMPLES", "150")), **SETTINGS)
@given(layouts(offline=False))
def test_generated_online_layouts_come_back_byte_for_byte(text: str) -> None:
    offline, back = online_there_and_back(text)
    assert back == text
