"""Hypothesis: generated worlds and off-line programs, and generated on-line programs, come back byte for byte.

The normal run checks 1,100 cases; ORC_HYPOTHESIS_EXAMPLES=N checks N of each kind.
"""

from __future__ import annotations

import os

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.offline_parser import parse_offline
from orc_rpl.syntax.offline_printer import print_offline
from orc_rpl.syntax.parser import parse
from orc_rpl.syntax.printer import print_program
from orc_rpl.transform.job import Job
from orc_rpl.transform.pipeline import TO_ONLINE, run, to_offline, to_online
from orc_rpl.world import loads_world
from tests.syntax import strategies as trees
from tests.syntax.test_offline_generated import offline_spellable
from tests.transform.strategies import programs, worlds

EXAMPLES = os.environ.get("ORC_HYPOTHESIS_EXAMPLES")
SETTINGS = dict(deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                                      HealthCheck.filter_too_much])


@st.composite
def cells(draw):  # type: ignore[no-untyped-def]
    world_text, entity = draw(worlds())
    return world_text, draw(programs(entity))


@settings(max_examples=int(EXAMPLES or 600), **SETTINGS)
@given(cells())
def test_offline_program_and_world_come_back_byte_for_byte(cell: tuple[str, str]) -> None:
    world_text, program_text = cell
    world = loads_world(world_text, "generated.yaml")
    text = print_offline(parse_offline(program_text, "generated.orl"))
    # The world reduction (tested on its own) is left out: reading YAML is most of the time here.
    online_text = print_program(run(Job(parse_offline(text), world), TO_ONLINE).program)
    job = to_offline(parse(online_text, "generated.rpl"), world)
    assert print_offline(job.program) == text, online_text
    assert job.world.dump() == world_text


def _online_spellable(program: n.Program) -> bool:
    return offline_spellable(program)


@settings(max_examples=int(EXAMPLES or 300), **SETTINGS)
@given(trees.programs.filter(_online_spellable))
def test_online_program_comes_back_byte_for_byte(program: n.Program) -> None:
    text = print_program(program)
    job = to_offline(parse(text, "generated.rpl"), None)
    world = loads_world(job.world.dump(), "made.yaml")
    assert print_program(to_online(parse_offline(print_offline(job.program)), world).program) == text


@settings(max_examples=int(EXAMPLES or 200), **SETTINGS)
@given(cells())
def test_online_form_of_a_generated_cell_comes_back_without_its_world(cell: tuple[str, str]) -> None:
    """The on-line program alone (as if written on the pendant) makes a world that gives it back exactly."""
    world_text, program_text = cell
    online_text = print_program(run(Job(parse_offline(program_text), loads_world(world_text, "g.yaml")), TO_ONLINE).program)
    job = to_offline(parse(online_text, "generated.rpl"), None)
    made = loads_world(job.world.dump(), "made.yaml")
    assert print_program(run(Job(parse_offline(print_offline(job.program)), made), TO_ONLINE).program) == online_text
