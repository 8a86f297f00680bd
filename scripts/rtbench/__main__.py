"""`python3 -m rtbench bench|report|compare|gen-scene [ARGS]`: see rtbench.cli."""

import sys

from rtbench.cli import main

if __name__ == "__main__":
    sys.exit(main())
