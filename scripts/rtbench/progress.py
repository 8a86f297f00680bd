"""A build's output condensed to a few lines a person can follow, with the
whole output kept in a log for when it fails. Standard library only: the
shell scripts run it (scripts/lib/steps.sh) as soon as Python is installed,
before pandas & co. are.

Ninja writes one `[N/M] description` line per edge when its output is not a
terminal; a first build is hundreds of them, a rebuild with nothing to do
is `ninja: no work to do.` This keeps a line every 10 % (and the last), and
the first line of each compiler warning (the rest stays in the log):

    building preset debug: 5/46 (10 %)
    ...
    src/x.cpp:3:5: warning: unused variable 'x' [-Wunused-variable]
    ...
    building preset debug: ran 46 of 46 steps in 212 s, 1 compiler warning

The closing line counts the steps that ran: ninja skips the rest of its
plan when an early step leaves their inputs unchanged (restat), and a failed
build stops early; whether it failed is the caller's to say.

As a filter: `python3 -m rtbench.progress LABEL --log FILE` reads the
build's output on stdin, writes all of it to FILE and the condensed lines to
stderr.
"""

from __future__ import annotations

import re
import sys
import time
from pathlib import Path

from rtbench import cli

NINJA_STEP = re.compile(r"^\[(\d+)/(\d+)\] ")
NINJA_NOTHING_TO_DO = "ninja: no work to do."
WARNING = re.compile(r": warning: ")
PERCENT_STEP = 10


class BuildProgress:
    """Turns build output lines into the few progress lines worth printing."""

    def __init__(self, label: str, clock=time.monotonic):
        self.label, self.clock = label, clock
        self.started = clock()
        self.next_percent = PERCENT_STEP
        self.done = self.total = self.warnings = 0
        self.up_to_date = False

    def feed(self, line: str) -> str | None:
        """The progress line this output line is worth, or None."""
        if WARNING.search(line):
            self.warnings += 1
            return line.rstrip("\n")
        if line.strip() == NINJA_NOTHING_TO_DO:
            self.up_to_date = True
            return None
        match = NINJA_STEP.match(line)
        if not match:
            return None
        self.done, self.total = int(match[1]), int(match[2])
        percent = 100 * self.done // self.total
        if self.done == self.total or percent < self.next_percent:
            return None  # the last step gets its line from summary()
        self.next_percent = (percent // PERCENT_STEP + 1) * PERCENT_STEP
        return f"{self.label}: {self.done}/{self.total} ({percent} %)"

    def summary(self) -> str:
        """The closing line, once the build has ended."""
        if self.up_to_date and not self.total:
            return f"{self.label}: up to date"
        text = f"{self.label}: ran {self.done} of {self.total} steps in {self.clock() - self.started:.0f} s"
        if self.warnings:
            text += f", {self.warnings} compiler warning{'s' if self.warnings != 1 else ''}"
        return text


def filter_stream(lines, log, out, label: str) -> BuildProgress:
    """Copies every line to `log` and the progress lines to `out`."""
    progress = BuildProgress(label)
    for line in lines:
        log.write(line)
        log.flush()
        message = progress.feed(line)
        if message:
            print(message, file=out, flush=True)
    print(progress.summary(), file=out, flush=True)
    return progress


def main(argv: list[str] | None = None) -> int:
    parser = cli.command_parser("python3 -m rtbench.progress", __doc__)
    parser.add_argument("label", help="what the lines start with, e.g. 'building preset debug'")
    parser.add_argument("--log", type=Path, required=True, help="where the whole output goes")
    args = parser.parse_args(argv)
    with open(args.log, "w", encoding="utf-8", errors="replace") as log:
        stdin = open(sys.stdin.fileno(), encoding="utf-8", errors="replace", closefd=False)
        filter_stream(stdin, log, sys.stderr, args.label)
    return 0


if __name__ == "__main__":
    sys.exit(main())
