#!/usr/bin/env python3
"""scripts/compare.py BASE NEW [-o DIR] [--fail-above 10%]: new runs against
base runs, configuration by configuration, the same as `python3 -m rtbench
compare` (the code: rtbench/compare_cli.py; `--help` lists the options).

`python3 scripts/compare.py ...` works as well as `scripts/compare.py ...`.
The comparison needs pandas, numpy, scipy, matplotlib and rich: when the
python3 that starts it lacks one, it runs under $RT_PYTHON, else Debian's
/usr/bin/python3, instead, or says what is missing and how to get it
(rtbench/interpreter.py).
"""

import sys

from rtbench import cli  # scripts/ is sys.path[0]: this file's directory; cli needs the standard library alone

if __name__ == "__main__":
    sys.exit(cli.script("compare", __file__, sys.argv[1:]))
