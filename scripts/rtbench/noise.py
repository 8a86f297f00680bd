"""Warnings that a measurement may be noisy, in the manner of hyperfine and
nanobench: they inform, they never stop a run or drop data.

Readers take the file-system root as a parameter so tests can point them at
a fake /sys or /proc; the checks themselves are pure functions.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

CPUFREQ_GLOB = "cpu[0-9]*/cpufreq/scaling_governor"
# A quiet machine sits near load 0; above a quarter of a core per core
# (and at least 0.5) other work is likely competing with the benchmark.
LOAD_PER_CORE_LIMIT = 0.25
LOAD_FLOOR = 0.5
# nanobench marks a result unstable at 5 % error; we use the same limit for
# the spread of the per-repetition medians of one configuration.
SPREAD_LIMIT = 0.05


def read_governors(cpu_root: Path = Path("/sys/devices/system/cpu")) -> dict[str, str]:
    """CPU name -> frequency governor, for every CPU whose governor is readable."""
    governors = {}
    for path in sorted(cpu_root.glob(CPUFREQ_GLOB)):
        try:
            governors[path.parent.parent.name] = path.read_text().strip()
        except OSError:
            continue
    return governors


def governor_warnings(governors: dict[str, str]) -> list[str]:
    """One warning naming the CPUs whose governor is not `performance`."""
    slow = sorted(cpu for cpu, g in governors.items() if g != "performance")
    if not slow:
        return []
    kinds = ", ".join(sorted({governors[c] for c in slow}))
    return [
        f"CPU frequency governor is {kinds} on {len(slow)} of {len(governors)} CPUs, not 'performance': "
        "clock changes add noise (e.g. `sudo cpupower frequency-set -g performance`)"
    ]


def read_load_average() -> float | None:
    """The 1-minute load average, or None where the OS does not tell."""
    try:
        return os.getloadavg()[0]
    except OSError:
        return None


def load_warnings(load1: float | None, cpu_count: int) -> list[str]:
    """A warning when the machine is already busy before the benchmark starts."""
    if load1 is None:
        return []
    limit = max(LOAD_FLOOR, LOAD_PER_CORE_LIMIT * cpu_count)
    if load1 <= limit:
        return []
    return [
        f"load average is {load1:.2f} on {cpu_count} logical CPUs before the start: other processes compete "
        "with the benchmark (close them or wait until the machine is idle)"
    ]


def spread_warnings(spreads: dict[str, float], limit: float = SPREAD_LIMIT) -> list[str]:
    """Warnings for configurations whose repetitions disagree by more than `limit`."""
    noisy = {k: v for k, v in spreads.items() if math.isfinite(v) and v > limit}
    if not noisy:
        return []
    worst = sorted(noisy.items(), key=lambda kv: -kv[1])
    listed = ", ".join(f"{k} ({v:.1%})" for k, v in worst[:5])
    more = f" and {len(worst) - 5} more" if len(worst) > 5 else ""
    return [
        f"{len(noisy)} configuration(s) vary by more than {limit:.0%} between repetitions: {listed}{more}; "
        "rerun on a quieter machine or with more repetitions"
    ]
