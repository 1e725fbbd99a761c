"""Allow `python -m codegen ...`."""

from bldc.cli import main

raise SystemExit(main())
