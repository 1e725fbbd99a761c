"""`python -m sim SPEC [-o DIR]`: see sim.cli."""

import sys

from sim.cli import main

sys.exit(main())
