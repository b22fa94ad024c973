"""`orc verify --scheduler tls://...`: a cluster whose scheduler, worker and client authenticate each other by TLS."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import pytest

from tests.verify.conftest import ROOT, SUBSET, alone, dask_cluster, orc, same_as_alone


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

    def tls(role: str) -> list[str]:
        return ["--tls-ca-file", "ca.pem", "--tls-cert", f"{role}.pem", "--tls-key", f"{role}.key"]

    with dask_cluster(tmp_path, workers=1, protocol="tls", tls=tls) as address:
        result = orc("verify", SUBSET[0], "--scheduler", address, "--tls-ca", str(tmp_path / "ca.pem"),
                     "--tls-cert", str(tmp_path / "client.pem"), "--tls-key", str(tmp_path / "client.key"),
                     "--json", str(tmp_path / "r.json"))
        refused = orc("verify", SUBSET[0], "--scheduler", address)
    assert result.returncode == 0, result.stderr
    [row] = json.loads((tmp_path / "r.json").read_text())["runs"]
    same_as_alone(row, alone(ROOT / SUBSET[0]))
    assert refused.returncode == 2 and "--tls-ca, --tls-cert and --tls-key" in refused.stderr
