#!/usr/bin/env python3
"""scripts/report.py RUN_DIR... [-o DIR]: the report of benchmark runs (or of
committed run archives), the same as `python3 -m rtbench report` (the code:
rtbench/report_writer.py; `--help` lists the options).

`python3 scripts/report.py ...` works as well as `scripts/report.py ...`.
The report needs pandas, numpy and matplotlib: when the python3 that starts
it lacks them, it runs under $RT_PYTHON, else Debian's /usr/bin/python3,
instead, or says what is missing and how to get it (rtbench/interpreter.py).
"""

import sys

from rtbench import cli  # scripts/ is sys.path[0]: this file's directory; cli needs the standard library alone

if __name__ == "__main__":
    sys.exit(cli.script("report", __file__, sys.argv[1:]))
