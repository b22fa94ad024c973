"""Shared helpers of the transformation tests: jobs from text, texts from jobs."""

from __future__ import annotations

from pathlib import Path

from orc_rpl.syntax.offline_parser import parse_offline
from orc_rpl.syntax.offline_printer import print_offline
from orc_rpl.syntax.parser import parse
from orc_rpl.syntax.printer import print_program
from orc_rpl.transform.job import Job
from orc_rpl.world import World, load_world

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
NESTED = HERE / "worlds" / "nested.yaml"


def nested() -> World:
    return load_world(NESTED)


def offline_job(text: str, world: World | None = None) -> Job:
    """A job holding an off-line program (dedented text) and a world."""
    return Job(parse_offline(text, "test.orl"), world or nested(), "test.orl", text)


def online_job(text: str, world: World | None = None) -> Job:
    return Job(parse(text, "test.rpl"), world or nested(), "test.rpl", text)


def online(job: Job) -> str:
    return print_program(job.program)


def offline(job: Job) -> str:
    return print_offline(job.program)
