"""The thesis' findings of several runs side by side (`scripts/report.py
--findings RUN [RUN ...] -o FILE.md`): one Markdown table, a row per claim,
a column per run, each cell the run's verdict and its figure with the 95 %
CI, as each run's own report has them (findings.evaluate; report_writer
evaluates each run and writes the table).

Runs are never pooled here: each is its own column, labelled by what sets
it apart from the thesis' setup (docs/thesis.md "The findings, checked"):
its machine (cores, CPU model) and its build's optimisation level.
"""

from __future__ import annotations

import math
from pathlib import Path

import pandas as pd

from rtbench import findings, names, tables


def run_label(run_dir: Path, frames: pd.DataFrame) -> str:
    """'2 cores, -O0 (CPU model; run name)': the machine and optimisation level of a run."""
    cores = ", ".join(str(c) for c in sorted(set(frames[names.LOGICAL_CORES])))
    levels = sorted(
        {findings.optimisation(f, b) for f, b in zip(frames[names.META_BUILD_COMPILER_FLAGS], frames[names.BUILD_TYPE])}
    )
    models = ", ".join(sorted(set(frames[names.CPU_MODEL])))
    return f"{cores} cores, {', '.join(levels)} ({models}; {run_dir.name})"


def cell(row) -> str:
    """'**reproduced** 1.52 [1.48, 1.57]': a run's verdict and its figure with the CI."""
    figure = findings.fmt_figure(row["measured"])
    if math.isfinite(row["ci_low"]):
        figure += f" [{findings.fmt_figure(row['ci_low'])}, {findings.fmt_figure(row['ci_high'])}]"
    return f"**{row['verdict']}** {figure}" if math.isfinite(row["measured"]) else f"**{row['verdict']}**"


def side_by_side(columns: list[tuple[str, pd.DataFrame]]) -> str:
    """The Markdown table of (label, findings) pairs: a row per claim of the first."""
    first = columns[0][1]
    rows = []
    for i, claim in enumerate(first.itertuples(index=False)):
        rows.append([claim.claim, claim.text, claim.line, *(cell(found.iloc[i]) for _, found in columns)])
    table = tables.Table(
        "findings-side-by-side",
        f"{findings.TITLE}: the runs side by side",
        ["#", "claim", "holds when", *(label for label, _ in columns)],
        rows,
        "lll" + "l" * len(columns),
        [NOTE],
    )
    return tables.to_markdown(table)


NOTE = (
    "Each cell: the run's verdict, its figure and the figure's 95% bootstrap CI, as the run's own report "
    "(section 'The thesis' findings, checked') gives them, with the reasons in its why column. Columns: the "
    "machine's logical cores and the build's optimisation level (the thesis: 8 cores of an Apple M1, -O0). "
    "The lines: docs/thesis.md, 'The findings, checked'."
)
