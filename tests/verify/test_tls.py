"""`orc verify --scheduler tls://...`: a cluster whose scheduler, worker and client authenticate each other by TLS."""

from __future__ import annotations

import json
import os
import shutil
import socket
import subprocess
import sys
from pathlib import Path

import pytest

from tests.verify.conftest import ROOT, SUBSET, alone, orc, same_as_alone


def _certificates(folder: Path) -> None:
    """A CA of the cluster and a certificate per role, as docs/security.md makes them."""
    def openssl(*args: str) -> None:
        subprocess.run(["openssl", *args], cwd=folder, check=True, capture_output=True)

    openssl("req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "2", "-subj", "/CN=orc-cluster-ca",
            "-keyout", "ca.key", "-out", "ca.pem")
    for role in ("scheduler", "worker", "client"):
        openssl("req", "-newkey", "rsa:2048", "-nodes", "-subj", f"/CN=orc-{role}", "-keyout", f"{role}.key",
                "-out", f"{role}.csr")
        openssl("x509", "-req", "-in", f"{role}.csr", "-CA", "ca.pem", "-CAkey", "ca.key", "-CAcreateserial",
                "-days", "2", "-out", f"{role}.pem")


@pytest.mark.sim
@pytest.mark.skipif(shutil.which("openssl") is None, reason="the openssl command is needed to make certificates")
def test_verify_on_a_tls_cluster_authenticated_by_certificates(tmp_path: Path) -> None:
    _certificates(tmp_path)
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    env = {**os.environ, "DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES": "0",
           "DASK_DISTRIBUTED__COMM__REQUIRE_ENCRYPTION": "True"}

    def tls(role: str) -> list[str]:
        return ["--tls-ca-file", "ca.pem", "--tls-cert", f"{role}.pem", "--tls-key", f"{role}.key"]

    processes = [subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--protocol", "tls",
                                   "--host", "127.0.0.1", "--port", str(port), "--no-dashboard", *tls("scheduler")],
                                  cwd=tmp_path, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        processes.append(subprocess.Popen(
            [sys.executable, "-m", "distributed.cli.dask_worker", f"tls://127.0.0.1:{port}", "--host", "127.0.0.1",
             "--nthreads", "1", "--no-dashboard", *tls("worker")], cwd=tmp_path, env=env,
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        address = f"tls://127.0.0.1:{port}"
        result = orc("verify", SUBSET[0], "--scheduler", address, "--tls-ca", str(tmp_path / "ca.pem"),
                     "--tls-cert", str(tmp_path / "client.pem"), "--tls-key", str(tmp_path / "client.key"),
                     "--json", str(tmp_path / "r.json"))
        assert result.returncode == 0, result.stderr
        [row] = json.loads((tmp_path / "r.json").read_text())["runs"]
        same_as_alone(row, alone(ROOT / SUBSET[0]))
        refused = orc("verify", SUBSET[0], "--scheduler", address)
        assert refused.returncode == 2 and "--tls-ca, --tls-cert and --tls-key" in refused.stderr
    finally:
        for process in reversed(processes):
            process.terminate()
        for process in processes:
            process.wait(timeout=30)
