"""The view's sending thread: the motion cycle hands over what to show and never waits on the web server."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

Job = Callable[[], None]


class Sender:
    """Runs jobs on one worker thread, in order. `always(job)` jobs all run (a planned path, trace points);
    of the `latest(job)` jobs only the newest waiting one runs (the robot's pose: an older one is already stale)."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._wake = threading.Condition(self._lock)
        self._jobs: list[Job] = []
        self._latest: Job | None = None
        self._busy = False
        self._closed = False
        self.error: BaseException | None = None   #: the first failure of a job (the view stops; the run goes on)
        self._thread = threading.Thread(target=self._loop, name="orc-view-sender", daemon=True)
        self._thread.start()

    def always(self, job: Job) -> None:
        with self._wake:
            self._jobs.append(job)
            self._wake.notify()

    def latest(self, job: Job) -> None:
        with self._wake:
            self._latest = job
            self._wake.notify()

    def drain(self) -> None:
        """Wait until every job handed over so far has run."""
        with self._wake:
            self._wake.wait_for(lambda: not (self._jobs or self._latest or self._busy) or self.error is not None)

    def close(self) -> None:
        """Run what is waiting, then stop the thread."""
        self.drain()
        with self._wake:
            self._closed = True
            self._wake.notify_all()
        self._thread.join()

    def _loop(self) -> None:
        while True:
            with self._wake:
                self._wake.wait_for(lambda: self._jobs or self._latest or self._closed)
                if self._closed and not (self._jobs or self._latest):
                    return
                jobs, self._jobs = self._jobs, []
                if self._latest is not None:
                    jobs.append(self._latest)
                    self._latest = None
                self._busy = True
            try:
                if self.error is None:
                    for job in jobs:
                        job()
                        time.sleep(0)  # the motion cycle may wait for the interpreter: let it have it between jobs
            except BaseException as error:  # a closed browser connection must not stop the robot
                self.error = error
            finally:
                with self._wake:
                    self._busy = False
                    self._wake.notify_all()
