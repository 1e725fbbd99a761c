"""Allow `python -m bldc ...` (the same as bldc-codegen)."""

from bldc.entry import main

raise SystemExit(main())
