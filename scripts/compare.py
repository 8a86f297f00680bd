#!/usr/bin/env bash
# scripts/compare.py BASE NEW [-o DIR] [--fail-above 10%]: new runs against
# base runs, configuration by configuration, the same as `python3 -m rtbench
# compare` (the code: scripts/rtbench/compare.py; `scripts/compare.py --help`
# lists the options).
#
# A bash script despite its name, like scripts/report.py and for the same
# reason: scripts/lib/python.sh picks the Python that has pandas, matplotlib,
# rich and scipy ($RT_PYTHON, else Debian's /usr/bin/python3).
set -euo pipefail
source "$(dirname "$0")/lib/python.sh"
rtbench compare "$@"
