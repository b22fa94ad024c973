"""docs/editors.md's Neovim configuration, run as written in a headless Neovim talking to `orc lsp`."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

#: Waits for the diagnostics (a hang guard for a busy machine, not a timing assertion), prints them, quits.
CHECK = """\
vim.cmd("edit prog.rpl")
local ok = vim.wait(120000, function() return #vim.diagnostic.get(0) > 0 end, 100)
for _, d in ipairs(vim.diagnostic.get(0)) do
  io.stdout:write(string.format("%d:%d-%d:%d %s\\n", d.lnum, d.col, d.end_lnum, d.end_col, d.message))
end
io.stdout:write(ok and "done\\n" or "no diagnostics\\n")
vim.cmd("qa!")
"""


def neovim_snippet() -> str:
    """The first Lua block of the Neovim section of docs/editors.md."""
    text = (ROOT / "docs" / "editors.md").read_text()
    section = text[text.index("## Neovim"):]
    match = re.search(r"```lua\n(.*?)```", section, re.S)
    assert match is not None, "docs/editors.md has no Lua block in its Neovim section"
    return match.group(1)


@pytest.mark.skipif(shutil.which("nvim") is None, reason="Neovim is not installed (.ci/run installs Debian's neovim)")
def test_the_documented_neovim_configuration_shows_an_error_from_orc_lsp(tmp_path: Path) -> None:
    (tmp_path / "init.lua").write_text(neovim_snippet())
    (tmp_path / "check.lua").write_text(CHECK)
    (tmp_path / "prog.rpl").write_text("TOOL grinder = POSE(0, 0, 150mm, 0, 90deg, 0)\nMOVE grinder TO p9\n")
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}",
           "XDG_STATE_HOME": str(tmp_path / "state"), "XDG_DATA_HOME": str(tmp_path / "data")}
    result = subprocess.run(["nvim", "--headless", "-u", "init.lua", "-c", "luafile check.lua"], cwd=tmp_path, env=env,
                            capture_output=True, text=True, timeout=300, stdin=subprocess.DEVNULL)
    assert "1:16-1:18 undefined name 'p9'" in result.stdout, result.stdout + result.stderr
    assert result.stdout.rstrip().endswith("done")
