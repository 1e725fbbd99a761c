"""The robustness campaign's options, defined once for `python -m sim.robustness` and
`bldc-codegen robustness` (argparse only: the CLI reads them without importing Dask)."""

from __future__ import annotations

import argparse
import os
from collections.abc import Callable

from codegen.argtypes import SEED

METHOD_NAMES = "none,conventional,improved,improved_r"


def _at_least(low: int, high: int | None = None, why: str = "") -> Callable[[str], int]:
    """argparse type: a whole number from `low` (to `high`, which `why` explains)."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
        if value < low:
            raise argparse.ArgumentTypeError(f"{value}: at least {low}")
        if high is not None and value > high:
            # --samples 999999999999 was an internal error (MemoryError: 7.28 TiB),
            # --workers 100000 started processes until it was killed
            raise argparse.ArgumentTypeError(
                f"{value} is out of range (allowed: [{low}, {high}]{why})"
            )
        return value

    return parse


#: The schemes of a Dask scheduler's address the CLI takes (distributed's registered
#: backends that reach another process; inproc is within one)
SCHEDULER_SCHEMES = ("tcp", "tls", "ws", "wss", "ucx")
SCHEDULER_ALLOWED = f"[{'|'.join(SCHEDULER_SCHEMES)}://]host:port, port 1-65535"


def scheduler_address(text: str) -> str:
    """argparse type: a Dask scheduler's address, checked before Dask is imported (a
    malformed one was an internal error from distributed's parser, "not a url"; a port
    of 99999 waited 30 s for a connection)."""
    address = text.strip()
    scheme, sep, rest = address.partition("://")
    if not sep:
        scheme, rest = "tcp", address
    host, colon, port = rest.rpartition(":")
    host = host[1:-1] if host.startswith("[") and host.endswith("]") else host  # IPv6
    problem = None
    if scheme not in SCHEDULER_SCHEMES:
        problem = f"unknown scheme {scheme!r}"
    elif not colon or not host or "/" in host or any(c.isspace() for c in host):
        problem = "no host:port"
    elif not port.isdigit() or not 1 <= int(port) <= 65535:
        problem = f"port {port!r} is not a port"
    if problem is not None:
        raise argparse.ArgumentTypeError(
            f"{text!r} is not a scheduler address: {problem} (allowed: {SCHEDULER_ALLOWED})"
        )
    return address


#: Upper bounds of the campaign's sizes: the results take samples x speeds x methods x
#: 3 doubles (100 000 x 100 x 4 x 3 x 8 B = 960 MB at most).
SAMPLES_MAX = 100_000
SPEEDS_MAX = 100
#: Local worker processes: a few per core (each imports NumPy and loads the cores).
WORKERS_MAX = 4 * (os.cpu_count() or 1)


def add_campaign_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--samples",
        type=_at_least(2, SAMPLES_MAX),
        default=1000,
        help="Latin-hypercube samples (1000)",
    )
    parser.add_argument(
        "--speeds",
        type=_at_least(1, SPEEDS_MAX),
        default=10,
        help="speeds over the spec's range (10)",
    )
    parser.add_argument(
        "--methods",
        default=METHOD_NAMES,
        help="comma-separated methods, each run as its generated C core (default: all four)",
    )
    parser.add_argument(
        "--plant",
        choices=("averaged", "switched"),
        default="averaged",
        help="averaged (default) or switched plant; switched also samples the carrier phase",
    )
    parser.add_argument("--seed", type=SEED, default=1, help="sampling seed (1)")
    parser.add_argument(
        "--workers",
        type=_at_least(1, WORKERS_MAX, f": 4 per core, {os.cpu_count() or 1} cores"),
        default=2,
        help="Dask LocalCluster worker processes (2)",
    )
    parser.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        type=scheduler_address,
        help="an existing Dask scheduler (e.g. tcp://host:8786) instead of a local cluster",
    )
    parser.add_argument("--chunk", type=_at_least(1), default=25, help="samples per Dask task (25)")
