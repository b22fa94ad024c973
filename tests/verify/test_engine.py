"""The cluster settings: local on loopback by default; a remote scheduler over TLS, or plain TCP only when asked."""

from __future__ import annotations

from pathlib import Path

import pytest

from orc_rpl.errors import UsageError
from orc_rpl.verify.engine import ClusterSettings, check_scheduler


@pytest.mark.parametrize("address", ["tcp://127.0.0.1:8786", "localhost:8786", "tcp://[::1]:8786"])
def test_a_scheduler_on_this_machine_needs_nothing_more(address: str) -> None:
    check_scheduler(ClusterSettings(scheduler=address))


def test_plain_tcp_to_another_machine_is_refused_unless_insecure() -> None:
    with pytest.raises(UsageError, match="unencrypted"):
        check_scheduler(ClusterSettings(scheduler="tcp://10.0.0.5:8786"))
    check_scheduler(ClusterSettings(scheduler="tcp://10.0.0.5:8786", allow_insecure=True))


def test_tls_needs_the_three_files(tmp_path: Path) -> None:
    with pytest.raises(UsageError, match="--tls-ca, --tls-cert and --tls-key"):
        check_scheduler(ClusterSettings(scheduler="tls://sched.plant:8786", tls_ca_file="ca.pem"))
    files = []
    for name in ("ca.pem", "client.pem", "client.key"):
        (tmp_path / name).write_text("x", encoding="utf-8")
        files.append(str(tmp_path / name))
    check_scheduler(ClusterSettings("tls://sched.plant:8786", 2, *files))
    with pytest.raises(UsageError, match="--tls-key: '.*missing.key' does not exist"):
        check_scheduler(ClusterSettings("tls://sched.plant:8786", 2, files[0], files[1], str(tmp_path / "missing.key")))


@pytest.mark.parametrize("address, message", [("http://h:1", "expected tcp://"), ("tcp://h", "expected HOST:PORT")])
def test_bad_addresses_are_usage_errors(address: str, message: str) -> None:
    with pytest.raises(UsageError, match=message):
        check_scheduler(ClusterSettings(scheduler=address))
