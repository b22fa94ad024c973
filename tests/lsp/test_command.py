"""`orc lsp` as a command: its help, and a clear message when the [lsp] extra is not installed."""

from __future__ import annotations

import subprocess
import sys

import pytest

from orc_rpl.cli import main


def test_orc_lsp_is_listed_and_has_help(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exit_:
        main(["lsp", "--help"])
    assert exit_.value.code == 0
    assert "language server" in capsys.readouterr().out


def test_without_pygls_orc_lsp_says_which_extra_to_install() -> None:
    # `sys.modules["pygls"] = None` makes `import pygls` fail as if the package were not installed.
    script = "import sys; sys.modules['pygls'] = None; from orc_rpl.cli import main; raise SystemExit(main(['lsp']))"
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120, stdin=subprocess.DEVNULL)
    assert result.returncode == 2
    assert result.stderr == "orc lsp: error: the language server needs pygls; install it with: pip install 'orc_rpl[lsp]'\n"
