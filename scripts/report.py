#!/usr/bin/env python3
"""Turns benchmark runs into a report: the thesis' tables 1-4 for our run,
the thesis' published numbers beside ours, speedup and Karp-Flatt, figures,
and a README that a person reads first.

    scripts/report.py runs/20250101T120000Z-paper -o report/

Several run directories are pooled (the same configuration in two runs
counts as more repetitions). Warm-up frames are excluded; outliers are
flagged, never dropped. A truncated or corrupted CSV stops the report with an
error naming the file.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

try:
    from rtbench import load, report, thesis
except ImportError as e:  # pandas or matplotlib missing for this interpreter
    # The same choice as scripts/lib/python.sh: $RT_PYTHON, else Debian's
    # /usr/bin/python3 (where apt put pandas), even when another python3
    # (pyenv, a venv) comes first on PATH. Tried once.
    other = os.environ.get("RT_PYTHON") or "/usr/bin/python3"
    untried = not os.environ.get("RT_REPORT_REEXEC")
    if untried and os.path.isfile(other) and os.path.realpath(other) != os.path.realpath(sys.executable):
        os.environ["RT_REPORT_REEXEC"] = "1"
        os.execv(other, [other, __file__, *sys.argv[1:]])
    sys.exit(f"report.py: {e}; run it with a Python that has pandas and matplotlib "
             f"(on Debian: scripts/setup-debian installs them for /usr/bin/python3)")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run_dirs", nargs="+", type=Path, metavar="RUN_DIR", help="run directory written by scripts/bench")
    parser.add_argument("-o", "--output", type=Path, default=Path("report"), help="report directory (default: report/)")
    parser.add_argument("--gpu-p", type=float, metavar="N",
                        help="processor count of the GPU for Karp-Flatt (default: per-device estimate, "
                             "data/gpu_processors.toml)")
    parser.add_argument("-q", "--quiet", action="store_true", help="print nothing but errors")
    args = parser.parse_args(argv)
    if args.gpu_p is not None and args.gpu_p <= 1:
        parser.error("--gpu-p must be greater than 1")

    try:
        inputs = report.gather(args.run_dirs, args.gpu_p)
        results = report.compute(inputs)
        written = report.write(inputs, results, args.output)
    except (load.RunDataError, thesis.ThesisDataError) as e:
        print(f"report.py: {e}", file=sys.stderr)
        return 1
    if not args.quiet:
        print(f"report: {args.output / 'README.md'} ({len(written)} files, {len(results.summary)} configurations)")
        for w in results.warnings:
            print(f"warning: {w}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
