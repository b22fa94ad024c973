"""The view's sending thread: the motion cycle hands over what to show and never waits on the web server."""

from __future__ import annotations

import threading
import time
from collections import deque
from collections.abc import Callable

from orc_rpl.motion import scheduling

Job = Callable[[], None]

#: How often the sending thread looks for work. The motion cycle never wakes it: waking a thread costs the waker
#: a thread switch (measured: about 1 ms a time on a busy two-core machine), which made paced cycles late.
POLL_S = 0.005


class Sender:
    """Runs jobs on one worker thread, in order. `always(job)` jobs all run (a planned path, trace points);
    of the `latest(job)` jobs only the newest runs (the robot's pose: an older one is already stale).

    Handing over takes no lock and wakes nothing (a deque append, an attribute store): the worker polls.
    """

    def __init__(self, poll_s: float = POLL_S) -> None:
        self.poll_s = poll_s
        self._jobs: deque[Job] = deque()
        self._latest: Job | None = None
        self._latest_run: Job | None = None
        self._closed = False
        self.error: BaseException | None = None   #: the first failure of a job (the view stops; the run goes on)
        self._thread = threading.Thread(target=self._loop, name="orc-view-sender", daemon=True)
        self._thread.start()

    def always(self, job: Job) -> None:
        self._jobs.append(job)

    def latest(self, job: Job) -> None:
        self._latest = job

    def _idle(self) -> bool:
        return not self._jobs and self._latest is self._latest_run

    def drain(self) -> None:
        """Wait until every job handed over so far has run (or the view failed)."""
        while not self._idle() and self.error is None and self._thread.is_alive():
            time.sleep(self.poll_s)

    def close(self) -> None:
        """Run what is waiting, then stop the thread."""
        self.drain()
        self._closed = True
        self._thread.join()

    def _loop(self) -> None:
        while not self._closed:
            time.sleep(self.poll_s)
            scheduling.follow_paced(2)  # holding the interpreter lock, it must not be preempted while a paced cycle waits
            try:
                while self._jobs and self.error is None:
                    self._jobs.popleft()()
                    time.sleep(0)  # the motion cycle may wait for the interpreter: let it have it between jobs
                latest = self._latest  # one read: the motion cycle may store a newer one meanwhile
                if latest is not self._latest_run and self.error is None:
                    latest()
                self._latest_run = latest
            except BaseException as error:  # a closed browser connection must not stop the robot
                self.error = error
                self._jobs.clear()
                self._latest_run = self._latest
