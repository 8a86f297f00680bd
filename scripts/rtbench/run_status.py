"""The status words of a run directory's manifest (RUN_DIR/manifest.json;
docs/bench-and-report.md's table of what a run directory holds lists them): one vocabulary for
the runner that writes them and for the loader and the report that read
them back. The manifest is written and read by rtbench alone (the raytracer
never sees it), so the words live here and not in schema/rt_schema.json,
which holds what the binary and the Python share.

StrEnum members are the plain strings themselves: they compare equal to the
words read back from a manifest, and json and f-strings write the word.
"""

from __future__ import annotations

import re
from enum import StrEnum


class RunStatus(StrEnum):
    """How one run (one repetition of one configuration) stands."""

    PENDING = "pending"  # planned, not started yet
    OK = "ok"  # exited 0 and left its CSV and metadata sidecar
    FAILED = "failed"  # a non-zero exit, a timeout, or an exit 0 without its outputs
    # never started: the probe failed, the binary or the device cannot run its renderer (or an option of it)
    UNAVAILABLE = "unavailable"
    INTERRUPTED = "interrupted"  # running when SIGINT or SIGTERM came; its outputs discarded


class ManifestStatus(StrEnum):
    """How the run directory as a whole stands."""

    RUNNING = "running"  # a runner works in it (or was killed without a word)
    COMPLETE = "complete"  # every planned run has run
    INTERRUPTED = "interrupted"  # stopped by SIGINT or SIGTERM; the manifest says by which


# The runs that an unfinished run has not run, and `scripts/bench --resume`
# runs: failed and unavailable runs ran (or never can) and are not missing.
NOT_RUN = (RunStatus.PENDING, RunStatus.INTERRUPTED)


# The longest probe reason the report shows.
PROBE_REASON_CHARS = 300


def probe_reason(run: dict) -> str:
    """What a failed probe said, from an unavailable run's stderr_tail: its
    exit status and the last line of its output, the error itself (a binary
    that does not know the flag prints its usage before it; the tail of that
    would hide the error's start)."""
    text = (run.get("stderr_tail") or "").strip()
    exit_status = re.match(r"exit -?\d+: ", text)
    prefix = exit_status.group(0) if exit_status else ""
    lines = [line.strip() for line in text[len(prefix) :].splitlines() if line.strip()]
    reason = prefix + (lines[-1] if lines else "")
    if len(reason) > PROBE_REASON_CHARS:
        reason = reason[: PROBE_REASON_CHARS - 1] + "…"
    return reason
