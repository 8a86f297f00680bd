#!/usr/bin/env bash
# scripts/report.py RUN_DIR... [-o DIR]: the report of benchmark runs, the
# same as `python3 -m rtbench report` (the code:
# scripts/rtbench/report_writer.py; `scripts/report.py --help` lists the
# options).
#
# A bash script despite its name, which stays for the command the README,
# the Nix app and the bench runner's messages give. The report needs pandas
# and matplotlib, and the one place that picks the Python that has them is
# scripts/lib/python.sh ($RT_PYTHON, else Debian's /usr/bin/python3 even when
# another python3 comes first on PATH), as for scripts/bench. So run it as a
# command, not as `python3 scripts/report.py`.
set -euo pipefail
source "$(dirname "$0")/lib/python.sh"
rtbench report "$@"
