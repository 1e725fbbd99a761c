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
        help="an existing Dask scheduler (e.g. tcp://host:8786) instead of a local cluster",
    )
    parser.add_argument("--chunk", type=_at_least(1), default=25, help="samples per Dask task (25)")
