"""Helpers of the view tests: the extra's presence, a headless Chromium, a run driven in-process."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path
from typing import IO

import pytest

ROOT = Path(__file__).resolve().parents[2]
CHROMIUM = "/usr/bin/chromium"
#: Headless Chromium renders WebGL in software (SwiftShader); it must never reach for the network.
CHROMIUM_ARGS = ["--no-sandbox", "--enable-unsafe-swiftshader", "--use-angle=swiftshader",
                 "--disable-background-networking", "--disable-component-update", "--no-first-run"]


def chromium_or_skip() -> str:
    """The Chromium executable, or skip: CI installs Debian's `chromium` package (see .ci/run)."""
    pytest.importorskip("playwright.sync_api", reason="playwright is part of the [test] extra")
    path = shutil.which("chromium") or (CHROMIUM if Path(CHROMIUM).exists() else None)
    if path is None:
        pytest.skip("no chromium on this machine (apt-get install chromium): the browser test of the 3D view is skipped")
    return path


def orc(*args: str, stdin: int | None = subprocess.DEVNULL) -> subprocess.Popen[str]:
    """`orc ARGS` as a child process with its output piped."""
    return subprocess.Popen([sys.executable, "-m", "orc_rpl", *args], cwd=ROOT, stdin=stdin,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def read_url(stream: IO[str]) -> str:
    """The view's address, from the line `orc` prints on standard error."""
    for line in stream:
        match = re.search(r"the 3D view is at (http://\S+)", line)
        if match:
            return match.group(1)
    raise AssertionError("orc never printed the view's address")
