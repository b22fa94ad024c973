"""What hover says about motion keywords, attributes, installed equipment and functions (no server needed)."""

from __future__ import annotations

import pytest

from orc_rpl.application.registry import default_registry
from orc_rpl.lsp.analysis import analyse
from orc_rpl.lsp.hover import hover_text
from orc_rpl.lsp.index import ProgramIndex

REGISTRY = default_registry()
TEXT = """\
TOOL gun = POSE(0, 0, 100mm, 0, 0, 0)
INSTALL laser AS LaserDistance WITH PORT = "sim"
CONST Vmax = 1.5mps
d = laser.Distance
GRINDMOVE gun TO OFFS(HERE, 0, 0, 10mm) WITH FORCE = 20N
"""


@pytest.mark.parametrize("line0, character, starts", [
    pytest.param(3, 12, "**laser.Distance** (LaserDistance value: a length (m))", id="sensor-value-of-installed-kind"),
    pytest.param(1, 20, "**LaserDistance**: INSTALL kind.", id="install-kind"),
    pytest.param(1, 37, "**PORT**: a string", id="install-attribute"),
    pytest.param(4, 3, "**GRINDMOVE**: ", id="motion-keyword"),
    pytest.param(4, 46, "**FORCE**: a force (N); default 30 N", id="motion-attribute-with-unit-and-default"),
    pytest.param(4, 18, "**OFFS**(", id="registry-function"),
    pytest.param(2, 7, "**Vmax**: constant, line 3", id="constant"),
])
def test_hover(line0: int, character: int, starts: str) -> None:
    analysis = analyse(TEXT, "/tmp/prog.rpl", REGISTRY)
    assert analysis.diagnostics == [] and analysis.program is not None
    text = hover_text(analysis, ProgramIndex(analysis.program), REGISTRY, line0, character)
    assert text is not None and text.startswith(starts), text


def test_a_constant_shows_its_value_in_si_units() -> None:
    analysis = analyse(TEXT, "/tmp/prog.rpl", REGISTRY)
    text = hover_text(analysis, ProgramIndex(analysis.program), REGISTRY, 2, 7)  # type: ignore[arg-type]
    assert text is not None and text.endswith("= 1.5 m/s")
