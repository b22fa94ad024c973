"""What `orc verify` and `orc sweep` share: the cluster options, and the `orc run` options they pass to every run."""

from __future__ import annotations

import argparse
import os
import shlex

from orc_rpl.commands import run as run_command
from orc_rpl.errors import UsageError
from orc_rpl.verify.engine import ClusterSettings


class _RunParser(argparse.ArgumentParser):
    """`orc run`'s own parser, raising instead of exiting, to check options before anything is submitted."""

    def error(self, message: str) -> None:  # type: ignore[override]
        raise UsageError(f"--run-args: orc run says: {message}")


def run_parser() -> argparse.ArgumentParser:
    """The parser `orc run` has in this installation (workers run an identical installation)."""
    top = _RunParser(prog="orc")
    return run_command.add_parser(top.add_subparsers(parser_class=_RunParser))


def run_accepts(option: str) -> bool:
    """True when `orc run` of this installation has the option (e.g. --seed and --plant once they exist)."""
    return option in run_parser()._option_string_actions


#: Options verify and sweep set themselves for every run.
_OWN = ("--summary-json", "--log", "--robot", "--world", "--set", "--realtime", "--plot", "--margins")


def run_args(text: str | None) -> tuple[str, ...]:
    """`--run-args='--plant ideal --seed 3'` split and checked against `orc run`'s parser."""
    if not text:
        return ()
    try:
        words = tuple(shlex.split(text))
    except ValueError as error:
        raise UsageError(f"--run-args: {error}") from None
    for word in words:
        if word.split("=")[0] in _OWN:
            raise UsageError(f"--run-args: {word.split('=')[0]} is set by this command itself")
    run_parser().parse_args(["PROGRAM.rpl", *words])
    return words


def add_cluster_options(parser: argparse.ArgumentParser) -> None:
    """--scheduler, --workers and the TLS files of a remote scheduler; --run-args for `orc run`."""
    parser.add_argument("--scheduler", metavar="ADDR", help="Dask scheduler to send runs to (tls://HOST:PORT or "
                        "tcp://HOST:PORT); default: a local cluster on 127.0.0.1")
    parser.add_argument("--workers", metavar="N", type=int, default=os.cpu_count() or 1,
                        help="worker processes of the local cluster, one thread each (default: the CPU count)")
    parser.add_argument("--tls-ca", metavar="FILE", help="CA certificate the scheduler's certificate is signed by")
    parser.add_argument("--tls-cert", metavar="FILE", help="this client's certificate (authenticates it)")
    parser.add_argument("--tls-key", metavar="FILE", help="this client's private key")
    parser.add_argument("--insecure", action="store_true",
                        help="allow a plain tcp:// scheduler on another machine (a network you trust)")
    parser.add_argument("--run-args", metavar="='ARGS'", help="further orc run options for every run, after an "
                        "equals sign and quoted, e.g. --run-args='--speed-override 50%%'")


def cluster_settings(args: argparse.Namespace) -> ClusterSettings:
    return ClusterSettings(scheduler=args.scheduler, workers=args.workers, tls_ca_file=args.tls_ca,
                           tls_cert_file=args.tls_cert, tls_key_file=args.tls_key, allow_insecure=args.insecure)


def check_output(option: str, path: str | None) -> None:
    """An output file's folder must exist (checked before anything runs)."""
    if path is not None and not os.path.isdir(os.path.dirname(os.path.abspath(path))):
        raise UsageError(f"{option}: the folder of '{path}' does not exist")
