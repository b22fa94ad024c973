"""Golden messages for bad world files: file, line, column, the source line, a caret and a hint."""

from __future__ import annotations

import textwrap

import pytest

from orc_rpl.errors import SourceError
from orc_rpl.world import load_world

CASES = {
    "cycle": (
        """\
        world:
          a:
            parent: b
            pose: [0, 0, 0, 0, 0, 0]
          b:
            parent: a
            pose: [0, 0, 0, 0, 0, 0]
        """,
        """\
        {f}:3:13: cycle in parents: a -> b -> a
            3 |     parent: b
              |             ^
              = hint: an object cannot be its own ancestor""",
    ),
    "missing_parent": (
        """\
        world:
          table:
            pose: [1m, 0, 0, 0, 0, 0]
          plate:
            parent: tabel
        """,
        """\
        {f}:5:13: unknown parent 'tabel' of 'plate'
            5 |     parent: tabel
              |             ^^^^^
              = hint: did you mean 'table'?""",
    ),
    "duplicate_name": (
        """\
        world:
          plate:
            pose: [1m, 0, 0, 0, 0, 0]
          plate:
            pose: [1m, 0, 0, 0, 0, 0]
        """,
        """\
        {f}:4:3: duplicate object name 'plate'
            4 |   plate:
              |   ^^^^^
              = hint: first defined at line 2""",
    ),
    "duplicate_frame": (
        """\
        world:
          plate:
            frames:
              p1: [0, 0, 0, 0, 0, 0]
              p1: [0, 0, 0, 0, 0, 0]
        """,
        """\
        {f}:5:7: duplicate name 'p1' in frames
            5 |       p1: [0, 0, 0, 0, 0, 0]
              |       ^^
              = hint: first defined at line 4""",
    ),
    "bad_pose": (
        """\
        world:
          plate:
            pose: [1m, 0, 0, 0, 0]
        """,
        """\
        {f}:3:11: a pose has 6 values [x, y, z, a, b, c], got 5
            3 |     pose: [1m, 0, 0, 0, 0]
              |           ^^^^^^^^^^^^^^^^""",
    ),
    "bad_unit": (
        """\
        world:
          plate:
            pose: [1200mm, 300mm, 750mm, 0, 0, 90grad]
        """,
        """\
        {f}:3:40: unknown unit 'grad' in '90grad'
            3 |     pose: [1200mm, 300mm, 750mm, 0, 0, 90grad]
              |                                        ^^^^^^
              = hint: units: mm cm m deg rad (a plain number is m or rad)""",
    ),
    "angle_for_length": (
        """\
        world:
          plate:
            frames:
              p1: [100mm, 90deg, 0, 0, 0, 0]
        """,
        """\
        {f}:4:19: pose value y must be a length, got an angle ('90deg')
            4 |       p1: [100mm, 90deg, 0, 0, 0, 0]
              |                   ^^^^^""",
    ),
    "unknown_key": (
        """\
        world:
          plate:
            frams:
              p1: [0, 0, 0, 0, 0, 0]
        """,
        """\
        {f}:3:5: unknown object attribute 'frams'
            3 |     frams:
              |     ^^^^^
              = hint: did you mean 'frames'?""",
    ),
    "yaml_syntax": (
        """\
        world:
          plate:
            pose: [1m, 0, 0, 0, 0, 0
          other:
            pose: [0, 0, 0, 0, 0, 0]
        """,
        """\
        {f}:4:8: YAML syntax error: expected ',' or ']', but got ':'
            4 |   other:
              |        ^
              = hint: while parsing a flow sequence (line 3)""",
    ),
    "tool_off_the_flange": (
        """\
        world:
          grinder:
            pose: [0, 0, 150mm, 0, 0, 0]
            tool: true
        """,
        """\
        {f}:4:5: tool 'grinder' is not mounted on the flange
            4 |     tool: true
              |     ^^^^
              = hint: give it (or its holder) 'parent: flange'""",
    ),
    "path_names_a_missing_frame": (
        """\
        world:
          casting:
            frames:
              e1: [0, 0, 0, 0, 0, 0]
              e2: [0, 0, 0, 0, 0, 0]
            paths:
              edge: [e1, e3]
        """,
        """\
        {f}:7:18: 'casting' has no frame 'e3'
            7 |       edge: [e1, e3]
              |                  ^^""",
    ),
    "anchor": (
        """\
        world:
          a:
            pose: &here [1m, 0, 0, 0, 0, 0]
          b:
            pose: *here
        """,
        """\
        {f}:3:11: anchor '&here': world files do not use anchors and aliases
            3 |     pose: &here [1m, 0, 0, 0, 0, 0]
              |           ^^^^^^^^^^^^^^^^^^^^^^^^^
              = hint: write the value out at each place""",
    ),
    "mesh_without_file": (
        """\
        world:
          casting:
            model:
              geometry: mesh
        """,
        """\
        {f}:4:7: geometry 'mesh' needs 'mesh: <file>'
            4 |       geometry: mesh
              |       ^""",
    ),
}


@pytest.mark.parametrize("source, expected", CASES.values(), ids=CASES.keys())
def test_bad_world_is_reported_with_file_line_and_caret(tmp_path, source: str, expected: str) -> None:
    path = tmp_path / "cell.yaml"
    path.write_text(textwrap.dedent(source))
    with pytest.raises(SourceError) as info:
        load_world(path)
    assert str(info.value) == textwrap.dedent(expected).format(f=path)


def test_several_mistakes_are_reported_in_one_pass_in_file_order(tmp_path) -> None:
    path = tmp_path / "cell.yaml"
    path.write_text("world:\n  a:\n    parent: nowhere\n  b:\n    pose: [1furlong, 0, 0, 0, 0, 0]\n")
    with pytest.raises(SourceError) as info:
        load_world(path)
    assert [d.location.line for d in info.value.diagnostics] == [3, 5]
