"""The robustness campaign's options, defined once for `python -m sim.robustness` and
`bldc-codegen robustness` (argparse only: the CLI reads them without importing Dask)."""

from __future__ import annotations

import argparse
from collections.abc import Callable

from codegen.argtypes import SEED

METHOD_NAMES = "none,conventional,improved,improved_r"


def _at_least(low: int) -> Callable[[str], int]:
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
        if value < low:
            raise argparse.ArgumentTypeError(f"{value}: at least {low}")
        return value

    return parse


def add_campaign_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--samples", type=_at_least(2), default=1000, help="Latin-hypercube samples (1000)"
    )
    parser.add_argument(
        "--speeds", type=_at_least(1), default=10, help="speeds over the spec's range (10)"
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
        "--workers", type=_at_least(1), default=2, help="Dask LocalCluster worker processes (2)"
    )
    parser.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="an existing Dask scheduler (e.g. tcp://host:8786) instead of a local cluster",
    )
    parser.add_argument("--chunk", type=_at_least(1), default=25, help="samples per Dask task (25)")
