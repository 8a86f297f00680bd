"""Compares two sets of benchmark runs: did NEW get faster or slower than
BASE, configuration by configuration, and what differs between the two
environments.

    scripts/compare.py BASE NEW                       # one run directory (or run archive) each
    scripts/compare.py --base A B --new C D           # several runs pooled per side, as in report.py
    scripts/compare.py BASE NEW -o cmp/ --fail-above 10%

Configurations are matched on the configuration key of the report (scene,
renderer, stage, accel, threads, lanes, size, build type, ...), less what the
machine decides rather than the benchmark: the Vulkan device and the SIMD
target (put them back with --key-with; --all-cores matches each side's
all-cores thread count with the other's). For each configuration present on
both sides, from the measured frames of all repetitions pooled:

  base and new median render_ms, the ratio new/base of the medians with a
  95 % percentile-bootstrap confidence interval (seeded: the same runs give
  the same output), the two-sided Mann-Whitney U test of the two sets of
  frame times, and a verdict: `faster` or `slower` where the change is
  significant (p < alpha, the interval excludes 1, and |ratio - 1| is at
  least the noise threshold), else `~`;

then the geometric mean of the ratios, the configurations found on one side
only, the frame-budget statistics of both sides (see rtbench.budget), and
every environment fact that differs between the two sides' run metadata (CPU,
cores, OS, compiler and flags, library versions, Vulkan device and driver,
git commit, Nix or not). It prints a table and, with -o DIR, writes
compare.md, compare.json and the ratio plot (compare.png, compare.svg).

Exit status: 0, or 1 when --fail-above is given and a configuration is
significantly slower by more than it (for CI gating), 2 on bad input (the
message names the file).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from rtbench import budget, cli, compare_input, compare_output, load
from rtbench.compare import DEFAULT_ALPHA, DEFAULT_NOISE, ENVIRONMENT_KEYS, CompareError, Options

# The command alone, its --help the docstring above: rtbench.compare computes the comparison,
# compare_input reads the two sides, compare_output writes the tables, JSON and plot.


def fraction(text: str) -> float:
    """'5%' or '0.05' -> 0.05."""
    try:
        value = float(text[:-1]) / 100.0 if text.endswith("%") else float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a fraction (0.05) or a percentage (5%)") from None
    if not 0 <= value < 1:
        raise argparse.ArgumentTypeError(f"{text!r} must lie in [0, 1) (or [0%, 100%))")
    return value


def parse_args(argv: list[str] | None, prog: str | None) -> tuple[argparse.Namespace, Options]:
    p = cli.command_parser(prog, __doc__)
    p.add_argument(
        "runs",
        nargs="*",
        type=Path,
        metavar="BASE NEW",
        help="two run directories or run archives (.tar.xz): the base and the new one",
    )
    p.add_argument("--base", nargs="+", type=Path, metavar="RUN", help="base runs, pooled (instead of BASE NEW)")
    p.add_argument("--new", nargs="+", type=Path, metavar="RUN", help="new runs, pooled (with --base)")
    p.add_argument(
        "--alpha",
        type=fraction,
        default=DEFAULT_ALPHA,
        help=f"significance level of the U test (default {DEFAULT_ALPHA})",
    )
    p.add_argument(
        "--noise",
        type=fraction,
        default=DEFAULT_NOISE,
        help=f"smallest relative change called faster or slower (default {DEFAULT_NOISE:.0%}%)",
    )
    p.add_argument(
        "--fail-above",
        type=fraction,
        metavar="FRACTION",
        help="exit 1 if a configuration is significantly slower by more than this (e.g. 10%%)",
    )
    budget.add_budgets_option(p, "frame budgets")
    p.add_argument(
        "--all-cores",
        action="store_true",
        help="match a configuration that ran on all of its machine's cores with the other side's "
        "all-cores one, whatever the two core counts (for comparing machines)",
    )
    p.add_argument(
        "--key-with",
        action="append",
        default=[],
        choices=ENVIRONMENT_KEYS,
        help="also match on this column (left out by default: it is the machine's, not the benchmark's)",
    )
    p.add_argument("-o", "--output", type=Path, metavar="DIR", help="write compare.md, compare.json and the plot here")
    p.add_argument("-q", "--quiet", action="store_true", help="print no table, only errors and failures")
    args = p.parse_args(argv)
    if args.runs and (args.base or args.new):
        p.error("give either BASE NEW or --base ... --new ..., not both")
    if args.runs:
        if len(args.runs) != 2:
            p.error(f"expected two runs, BASE and NEW, got {len(args.runs)} (pool several with --base ... --new ...)")
        args.base, args.new = [args.runs[0]], [args.runs[1]]
    if not (args.base and args.new):
        p.error("nothing to compare: give BASE NEW, or --base RUN... --new RUN...")
    options = Options(
        args.alpha, args.noise, args.fail_above, tuple(args.budget_ms), args.all_cores, tuple(args.key_with)
    )
    return args, options


def main(argv: list[str] | None = None, prog: str | None = None) -> int:
    args, options = parse_args(argv, prog)
    prog = prog or "compare"
    try:
        comparison = compare_input.compare_paths(args.base, args.new, options)
        if args.output:
            compare_output.write(comparison, args.output)
    except (load.RunDataError, CompareError) as e:
        print(f"{prog}: {e}", file=sys.stderr)
        return 2
    if not args.quiet:
        compare_output.print_terminal(comparison)
    failures = comparison.failures()
    for failure in failures:
        print(f"{prog}: {failure} is slower by more than {options.fail_above:.0%} (--fail-above)", file=sys.stderr)
    return 1 if failures else 0
