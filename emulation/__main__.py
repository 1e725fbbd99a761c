"""`python -m emulation`: the `make bench` driver (emulation/bench.py)."""

from emulation.bench import main

raise SystemExit(main())
