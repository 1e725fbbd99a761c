"""The `bldc-codegen` entry point: imports the command line inside the interrupt
handling, so a Ctrl-C while the heavy modules load (Jinja2, SymPy, NumPy) says
"interrupted" in one line, as one while a command runs does (`bldc.cli.main`)."""

from __future__ import annotations

import sys
from collections.abc import Sequence


def main(argv: Sequence[str] | None = None) -> int:
    try:
        from bldc.cli import main as run
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    return run(argv)
