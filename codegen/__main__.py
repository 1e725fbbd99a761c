"""Allow `python -m codegen ...`."""

from bldc.entry import main

raise SystemExit(main())
