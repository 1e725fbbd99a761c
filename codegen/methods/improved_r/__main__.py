import sys

from codegen.methods.improved_r.summary import main

sys.exit(main())
