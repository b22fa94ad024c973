"""The checker never crashes: any tree the parser can produce gets diagnostics, not a traceback."""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings

from orc_rpl.application.registry import default_registry
from orc_rpl.checking.checker import check_program
from orc_rpl.errors import Diagnostic
from orc_rpl.syntax import nodes as n
from tests.syntax.strategies import programs

REGISTRY = default_registry()


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(programs)
def test_checker_reports_instead_of_crashing(program: n.Program) -> None:
    for diagnostic in check_program(program, "gen.rpl", REGISTRY):
        assert isinstance(diagnostic, Diagnostic) and diagnostic.message
