#!/usr/bin/env python3
"""scripts/gen_scene.py NAME... -o DIR: writes the committed scenes (or a
random one), the same as `python3 -m rtbench gen-scene` (the code:
rtbench/scenes.py; `--help` lists the options). Standard library only, so
any Python 3 runs it: `python3 scripts/gen_scene.py ...` works too.
"""

import sys

from rtbench import cli  # scripts/ is sys.path[0]: this file's directory

if __name__ == "__main__":
    sys.exit(cli.run("gen-scene", sys.argv[1:]))
