"""`python -m emulation`: the `make bench` driver (emulation/bench.py)."""

from codegen.interrupts import exit_status
from emulation.bench import main

raise SystemExit(exit_status(main))
