import sys

from codegen.improved_r_rule.summary import main

sys.exit(main())
