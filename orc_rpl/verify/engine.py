"""The Dask side: a local cluster on loopback (or the scheduler given), runs streamed back as they finish, one retry."""

from __future__ import annotations

import importlib.util
import ipaddress
import logging
import os
import uuid
from dataclasses import dataclass
from typing import Any, Callable, Iterator, Sequence
from urllib.parse import urlsplit

from orc_rpl.errors import OrcError, UsageError

#: How long a client waits for a remote scheduler before giving up.
CONNECT_TIMEOUT_S = 20

#: Worker deaths a run survives: the first is retried, the second is reported (DESIGN: once and only once).
RETRIES_AFTER_WORKER_DEATH = 1


@dataclass(frozen=True, slots=True)
class ClusterSettings:
    """Where runs go: a local cluster of `workers` processes, or the scheduler at `scheduler` (TLS files if any)."""

    scheduler: str | None = None
    workers: int = 2
    tls_ca_file: str | None = None
    tls_cert_file: str | None = None
    tls_key_file: str | None = None
    allow_insecure: bool = False          #: a plain-TCP scheduler that is not on this machine


@dataclass(frozen=True, slots=True)
class Finished:
    """One item done: its result, or why there is none (its worker died on every attempt, or the task raised)."""

    index: int
    result: Any
    attempts: int
    failure: str | None = None


def _is_loopback(host: str) -> bool:
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def check_scheduler(settings: ClusterSettings) -> None:
    """Refuse what would send our runs (and so our code) to another machine in the clear, before connecting."""
    address = settings.scheduler
    if address is None:
        return
    parts = urlsplit(address if "://" in address else f"tcp://{address}")
    tls_files = (settings.tls_ca_file, settings.tls_cert_file, settings.tls_key_file)
    if parts.scheme not in ("tcp", "tls"):
        raise UsageError(f"--scheduler: expected tcp://HOST:PORT or tls://HOST:PORT, got {address!r}")
    if not parts.hostname or parts.port is None:
        raise UsageError(f"--scheduler: expected HOST:PORT in {address!r}")
    if parts.scheme == "tls" and not all(tls_files):
        raise UsageError("--scheduler tls://...: give --tls-ca, --tls-cert and --tls-key (see docs/security.md)")
    if parts.scheme == "tcp" and any(tls_files):
        raise UsageError("--tls-*: the scheduler address must start with tls:// to use them")
    if parts.scheme == "tcp" and not _is_loopback(parts.hostname) and not settings.allow_insecure:
        raise UsageError(f"--scheduler {address}: plain TCP to another machine sends programs and results unencrypted "
                         "and lets anyone who reaches the port run code; use tls:// with certificates, "
                         "or --insecure on a network you trust (see docs/security.md)")
    for option, path in zip(("--tls-ca", "--tls-cert", "--tls-key"), tls_files):
        if path is not None and not os.path.isfile(path):
            raise UsageError(f"{option}: '{path}' does not exist")


class Engine:
    """A Dask client for the duration of a `with` block; `results()` runs a function over items on its workers."""

    def __init__(self, settings: ClusterSettings) -> None:
        check_scheduler(settings)
        if importlib.util.find_spec("distributed") is None:
            raise UsageError("this command needs Dask distributed: pip install 'orc_rpl[verify]'")
        if settings.workers < 1:
            raise UsageError(f"--workers must be at least 1, got {settings.workers}")
        self.settings = settings
        self.client: Any = None
        self._cluster: Any = None

    def __enter__(self) -> Engine:
        from distributed import Client, LocalCluster
        from distributed.security import Security

        s = self.settings
        if s.scheduler is None:
            # Loopback only, one thread per worker process (a run is single-threaded and captures its output),
            # no dashboard; a worker death fails the task at once so that our single retry is the only one.
            os.environ.setdefault("DASK_LOGGING__DISTRIBUTED", "error")  # inherited by the worker processes
            self._cluster = LocalCluster(n_workers=s.workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                                         dashboard_address=None, scheduler_kwargs={"allowed_failures": 0},
                                         silence_logs=logging.ERROR)
            self.client = Client(self._cluster)
            return self
        security = None
        if s.tls_ca_file is not None:
            security = Security(tls_ca_file=s.tls_ca_file, tls_client_cert=s.tls_cert_file,
                                tls_client_key=s.tls_key_file, require_encryption=True)
        try:
            self.client = Client(s.scheduler, security=security, timeout=f"{CONNECT_TIMEOUT_S}s")
        except (OSError, TimeoutError, ValueError) as error:  # refused, timed out, a TLS file that is no certificate
            raise OrcError(f"cannot reach the Dask scheduler at {s.scheduler}: {error}") from None
        return self

    def __exit__(self, *exc: Any) -> None:
        if self.client is not None:
            self.client.close()
        if self._cluster is not None:
            self._cluster.close()

    def worker_count(self) -> int:
        """Workers the scheduler knows now."""
        return len(self.client.scheduler_info().get("workers", {}))

    def results(self, function: Callable[..., Any], items: Sequence[Any], *leading: Any) -> Iterator[Finished]:
        """`function(*leading, item)` for every item on the workers, yielded as each finishes.

        A run whose worker died is submitted once more under a new key; a second death is yielded as a failure,
        never dropped. KeyboardInterrupt cancels every run not yet finished and propagates.
        """
        from distributed import as_completed
        from distributed.scheduler import KilledWorker

        batch = uuid.uuid4().hex[:12]  # keys unique on a scheduler other clients share

        def submit(index: int, attempt: int) -> Any:
            return self.client.submit(function, *leading, items[index], key=f"orc-run-{batch}-{index}-{attempt}",
                                      pure=False)

        live: dict[str, tuple[int, int, Any]] = {}  # key -> (item, attempt, future) of every run not yet yielded
        for index in range(len(items)):
            future = submit(index, 1)
            live[future.key] = (index, 1, future)
        pending = as_completed([future for _, _, future in live.values()])
        try:
            for future in pending:
                index, attempt, _ = live.pop(future.key)
                if future.status == "finished":
                    yield Finished(index, future.result(), attempt)
                    continue
                error = future.exception()
                if isinstance(error, KilledWorker) and attempt <= RETRIES_AFTER_WORKER_DEATH:
                    retry = submit(index, attempt + 1)
                    live[retry.key] = (index, attempt + 1, retry)
                    pending.add(retry)
                    continue
                reason = ("its worker died on every attempt" if isinstance(error, KilledWorker)
                          else f"{type(error).__name__}: {error}")
                yield Finished(index, None, attempt, reason)
        except (KeyboardInterrupt, GeneratorExit):
            self.client.cancel([future for _, _, future in live.values()], force=True)
            raise
