"""A worker that dies mid-run: the run is retried once on another worker, and a second death is reported, not dropped."""

from __future__ import annotations

import os
import signal
import threading
import time

import pytest

from orc_rpl.cli import main
from orc_rpl.verify.engine import ClusterSettings, Engine
from orc_rpl.verify.judge import judge
from orc_rpl.verify.programs import Expectation
from orc_rpl.verify.task import RunSpec, run_task
from tests.verify.conftest import ROOT, alone

PROGRAM = ROOT / "programs/online/demo_recover.rpl"


def _kill_workers_running(engine: Engine, attempts: set[int], stop: threading.Event) -> None:
    """Kill (SIGKILL) the worker process that holds attempt N of the run, for every N in `attempts`."""
    killed: set[int] = set()
    while not stop.is_set() and killed != attempts:
        for address, keys in engine.client.processing().items():
            for key in keys:
                attempt = int(str(key).rsplit("-", 1)[1])
                if attempt in attempts and attempt not in killed:
                    pids = engine.client.run(os.getpid, workers=[address])
                    os.kill(pids[address], signal.SIGKILL)
                    killed.add(attempt)
        time.sleep(0.02)


def _run_with_kills(attempts: set[int]) -> list:
    spec = RunSpec(str(PROGRAM), "irb2400")
    stop = threading.Event()
    with Engine(ClusterSettings(workers=2)) as engine:
        killer = threading.Thread(target=_kill_workers_running, args=(engine, attempts, stop), daemon=True)
        killer.start()
        try:
            return list(engine.results(run_task, [spec], main))
        finally:
            stop.set()
            killer.join(timeout=10)


@pytest.mark.sim
def test_a_worker_killed_mid_run_is_retried_once_with_the_same_result() -> None:
    [done] = _run_with_kills({1})
    assert done.attempts == 2 and done.failure is None
    row = judge("demo_recover.rpl", "irb2400", Expectation(), done.result, done.attempts, done.failure, {})
    reference = alone(PROGRAM)
    assert (row.verdict, row.attempts, row.cycle_time_s, row.motions) == \
        ("ok", 2, reference["cycle_time_s"], reference["motions"])


@pytest.mark.sim
def test_a_run_whose_worker_dies_twice_is_reported_as_lost() -> None:
    [done] = _run_with_kills({1, 2})
    assert (done.result, done.attempts, done.failure) == (None, 2, "its worker died on every attempt")
    row = judge("demo_recover.rpl", "irb2400", Expectation(), done.result, done.attempts, done.failure, {})
    assert (row.status, row.verdict, row.reasons) == ("lost", "FAIL", ("not run: its worker died on every attempt",))
