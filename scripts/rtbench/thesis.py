"""The thesis' published numbers (data/thesis/) and what they recompute to.

The table layout of the report (which renderers each of tables 1-4 shows, for
which stage) is read from the thesis' own tables.csv rather than written
down a second time.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from rtbench import metrics, names

THESIS_DIR = names.REPO_ROOT / "data" / "thesis"
TABLES_FILE = THESIS_DIR / "tables.csv"
REPORTED_FILE = THESIS_DIR / "metrics_reported.csv"
TABLE_COLUMNS = ["table", "stage", "renderer", "scene", "ms"]


class ThesisDataError(ValueError):
    """The thesis data files do not match the schema; names the file."""


@dataclass(frozen=True)
class TableSpec:
    """One of the thesis' tables: its number, stage, renderers and scenes."""

    number: int
    stage: str
    renderers: tuple[str, ...]
    scenes: tuple[str, ...]


def load_tables(path: Path = TABLES_FILE) -> pd.DataFrame:
    """tables.csv, checked: known renderers and stages, positive times."""
    df = pd.read_csv(path)
    if list(df.columns) != TABLE_COLUMNS:
        raise ThesisDataError(f"{path}: expected columns {TABLE_COLUMNS}, found {list(df.columns)}")
    _check_names(path, df)
    if not (df["ms"] > 0).all():
        raise ThesisDataError(f"{path}: every ms must be positive")
    return df


def load_reported(path: Path = REPORTED_FILE) -> pd.DataFrame:
    """metrics_reported.csv: the speedups and Karp-Flatt values the text states."""
    df = pd.read_csv(path)
    _check_names(path, df)
    return df


def _check_names(path: Path, df: pd.DataFrame) -> None:
    bad = sorted(set(df["renderer"]) - set(names.RENDERERS)) + sorted(set(df["stage"]) - set(names.STAGES))
    if bad:
        raise ThesisDataError(f"{path}: names not in schema/rt_schema.json: {', '.join(bad)}")


def table_layout(tables: pd.DataFrame) -> list[TableSpec]:
    """Tables 1-4 as the thesis printed them: renderers and scenes in the order
    they first appear in its data."""
    specs = []
    for number, rows in tables.groupby("table", sort=True):
        stages = rows["stage"].unique()
        if len(stages) != 1:
            raise ThesisDataError(f"thesis table {number} mixes stages {list(stages)}")
        specs.append(
            TableSpec(int(number), str(stages[0]), tuple(rows["renderer"].unique()), tuple(rows["scene"].unique()))
        )
    return specs


def stage_times(tables: pd.DataFrame) -> pd.DataFrame:
    """One time per (stage, renderer, scene): the thesis repeats some figures
    (e.g. the sequential times of tables 3 and 4 are the same run)."""
    return tables.drop_duplicates(["stage", "renderer", "scene"])[["stage", "renderer", "scene", "ms"]]


def recomputed_speedups(tables: pd.DataFrame, reference: str | None = None) -> pd.DataFrame:
    """S = T_ref / T for every published non-reference time."""
    reference = reference or names.reference_renderer()
    times = stage_times(tables)
    ref = times[times["renderer"] == reference][["stage", "scene", "ms"]].rename(columns={"ms": "ref_ms"})
    out = times[times["renderer"] != reference].merge(ref, on=["stage", "scene"])
    out["speedup"] = [metrics.speedup(r, t) for r, t in zip(out["ref_ms"], out["ms"])]
    return out


def reported_vs_recomputed(tables: pd.DataFrame, reported: pd.DataFrame) -> pd.DataFrame:
    """Each metric the thesis states, beside the value its own table gives
    with the same p: the speedups agree, the Karp-Flatt values do not."""
    speedups = recomputed_speedups(tables)
    wide = reported.pivot_table(index=["stage", "scene", "renderer", "p"], columns="metric", values="reported")
    wide = wide.reset_index().rename(columns={"speedup": "speedup_reported", "karp_flatt": "karp_flatt_reported"})
    out = wide.merge(
        speedups[["stage", "scene", "renderer", "ref_ms", "ms", "speedup"]], on=["stage", "scene", "renderer"]
    )
    out = out.rename(columns={"speedup": "speedup_recomputed"})
    out["karp_flatt_recomputed"] = [metrics.karp_flatt(s, p) for s, p in zip(out["speedup_recomputed"], out["p"])]
    out["_stage"] = out["stage"].map(names.stage_order)
    out["_renderer"] = out["renderer"].map(names.renderer_order)
    out = out.sort_values(["_stage", "scene", "_renderer"]).drop(columns=["_stage", "_renderer"])
    return out.reset_index(drop=True)[
        [
            "stage",
            "scene",
            "renderer",
            "p",
            "ref_ms",
            "ms",
            "speedup_reported",
            "speedup_recomputed",
            "karp_flatt_reported",
            "karp_flatt_recomputed",
        ]
    ]
