"""Frame-budget statistics: how often, and for how long in a row, a frame
misses its deadline, and how much consecutive frames differ.

A frame budget is a deadline for the whole frame, so these statistics are of
the frame time, the sum of the host phases the frame loop times (the
schema's `phases`: Update, Render, Present), not of render_ms alone:

- share over budget: the fraction of measured frames that took longer than
  the budget;
- longest run over budget: the most consecutive measured frames of one run
  over it (frames of different repetitions are never consecutive);
- jitter: the median absolute difference between consecutive measured
  frames of one run (the frame-to-frame change a viewer sees, which a median
  or a standard deviation over all frames does not show);
- p99 and max of the frame time.

Pure functions over arrays and the tidy frame; no I/O.
"""

from __future__ import annotations

import argparse
import math

import numpy as np
import pandas as pd

from rtbench import names, stats, tables

# 60 and 30 frames per second.
DEFAULT_BUDGETS_MS = (16.67, 33.33)


def positive_ms(text: str) -> float:
    """argparse type of a frame budget: a positive, finite number of milliseconds."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"{text!r} is not a positive number of milliseconds")
    return value


def add_budgets_option(parser: argparse.ArgumentParser, what: str) -> None:
    """--budget-ms, as the report and the comparison both take it; its help
    says `what` the budgets are for, and the default."""
    default = " ".join(str(ms) for ms in DEFAULT_BUDGETS_MS)
    parser.add_argument(
        "--budget-ms",
        type=positive_ms,
        nargs="+",
        default=list(DEFAULT_BUDGETS_MS),
        metavar="MS",
        help=f"{what} (default: {default})",
    )


# The derived column: the whole frame, every timed host phase added up.
FRAME_MS = "frame_ms"


def frame_ms(frames: pd.DataFrame) -> pd.Series:
    """Each frame's time: the sum of its phase columns."""
    return frames[names.PHASE_MS].sum(axis=1, min_count=len(names.PHASE_MS))


def share_over(values, budget_ms: float) -> float:
    """The fraction of frames slower than the budget; NaN without frames."""
    x = stats.finite(values)
    return float(np.mean(x > budget_ms)) if x.size else math.nan


def longest_run_over(values, budget_ms: float) -> int:
    """The most consecutive frames (in the given order) slower than the budget."""
    longest = current = 0
    for over in np.asarray(values, dtype=float) > budget_ms:
        current = current + 1 if over else 0
        longest = max(longest, current)
    return longest


def consecutive_differences(values) -> np.ndarray:
    """|x[i+1] - x[i]| of a series in frame order."""
    return np.abs(np.diff(stats.finite(values)))


def jitter(series: list) -> float:
    """Median absolute difference of consecutive frames, over the differences
    of every series (one per run) pooled; NaN where no series has two frames."""
    diffs = [consecutive_differences(s) for s in series]
    pooled = np.concatenate(diffs) if diffs else np.array([])
    return float(np.median(pooled)) if pooled.size else math.nan


def share_column(budget_ms: float) -> str:
    return f"over_{budget_ms:g}ms_share"


def run_column(budget_ms: float) -> str:
    return f"over_{budget_ms:g}ms_longest_run"


def budget_stats(series: list, budgets_ms) -> dict[str, float]:
    """Every budget statistic of one configuration, from its runs' measured
    frame times, each series in frame order."""
    pooled = np.concatenate([stats.finite(s) for s in series]) if series else np.array([])
    row = {
        "n": int(pooled.size),
        "median": stats.median(pooled),
        "p99": stats.percentile(pooled, 99),
        "max": float(pooled.max()) if pooled.size else math.nan,
        "jitter": jitter(series),
    }
    for budget in budgets_ms:
        row[share_column(budget)] = share_over(pooled, budget)
        row[run_column(budget)] = max((longest_run_over(s, budget) for s in series), default=0)
    return row


def runs_in_order(group: pd.DataFrame, value: str = FRAME_MS) -> list[np.ndarray]:
    """The measured frame times of each run (repetition) of one configuration,
    in frame order."""
    ordered = group.sort_values([names.REPETITION, names.FRAME])
    return [part[value].to_numpy(dtype=float) for _, part in ordered.groupby(names.REPETITION, sort=True)]


def summarize_budgets(frames: pd.DataFrame, budgets_ms=DEFAULT_BUDGETS_MS) -> pd.DataFrame:
    """One row per configuration (stats.CONFIG_KEYS): the budget statistics
    of its measured frames, all repetitions."""
    meas = stats.measured(frames)
    meas = meas.assign(**{FRAME_MS: frame_ms(meas)})
    rows = []
    for key, group in meas.groupby(stats.CONFIG_KEYS, sort=False, dropna=False):
        rows.append({**dict(zip(stats.CONFIG_KEYS, key)), **budget_stats(runs_in_order(group), budgets_ms)})
    columns = [*stats.CONFIG_KEYS, *stat_columns(budgets_ms)]
    return stats.sort_configs(pd.DataFrame(rows, columns=columns))


def stat_columns(budgets_ms) -> list[str]:
    return ["n", "median", "p99", "max", "jitter", *(c for b in budgets_ms for c in (share_column(b), run_column(b)))]


def budget_table(budgets: pd.DataFrame, budgets_ms) -> tables.Table:
    """The report's frame-budget table: every configuration."""
    rows = []
    for r in budgets.to_dict("records"):
        over = [
            cell
            for b in budgets_ms
            for cell in (tables.fmt_percent(r[share_column(b)]), tables.fmt_int(r[run_column(b)]))
        ]
        rows.append(
            [
                *tables.config_cells(r),
                tables.fmt_int(r["n"]),
                tables.fmt_ms(r["median"]),
                tables.fmt_ms(r["p99"]),
                tables.fmt_ms(r["max"]),
                tables.fmt_ms(r["jitter"]),
                *over,
            ]
        )
    headers, align = tables.config_headers()
    budget_headers = [h for b in budgets_ms for h in (f"> {b:g} ms", "longest run")]
    return tables.Table(
        "frame-budget",
        "Frame budget: the whole frame (update + render + present) [ms]",
        [*headers, "n", "median", "p99", "max", "jitter", *budget_headers],
        rows,
        align + "rrrrr" + "rr" * len(budgets_ms),
        [budget_note(budgets_ms)],
    )


def budget_note(budgets_ms) -> str:
    texts = ", ".join(f"{b:g} ms ({1000 / b:.0f} fps)" for b in budgets_ms)
    return (
        f"Budgets {texts}. '> B ms': share of measured frames over the budget; 'longest run': the most "
        "consecutive frames of one run over it; jitter: median |difference| between consecutive frames of "
        "one run. Frame time = update_ms + render_ms + present_ms of the frame."
    )
