"""Allow `python -m bldc ...` (the same as bldc-codegen)."""

from bldc.cli import main

raise SystemExit(main())
