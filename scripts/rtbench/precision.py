"""The thesis' half-precision experiment (docs/thesis.md, "Stages"): each f16
configuration of a run against its f32 twin, and how far each image is from
the double-precision reference.

The thesis halved SIMD precision to fit eight pixels into a register and
found it twice as fast but the image unusable. A profile's `precisions`
runs a renderer in both (--precision f32|f16), its `agreement` adds the
image of frame 0 against the double-precision reference to each run's
metadata (--agreement), which the loader reads into the AGREEMENT_COLUMNS.
Here: speedup f32/f16 from the median render times with the bootstrap CI of
stats.median_ratio_ci, and whether each image agrees under the render
model's rule (docs/render-model.md section 8).
"""

from __future__ import annotations

import math

import pandas as pd

from rtbench import names, stats, tables
from rtbench.run_status import RunStatus, probe_reason

# docs/render-model.md section 8 (src/core/image.h, ImageAgreement::agrees):
# at least 99.5 % of the pixels within 2/255 in each channel, and PSNR >= 40 dB.
AGREES_WITHIN = 0.995
AGREES_PSNR_DB = 40.0

SPEEDUP, SPEEDUP_LOW, SPEEDUP_HIGH = "speedup", "speedup_low", "speedup_high"
# The columns of one side (f32 or f16) of a row: its median and its agreement.
SIDE_COLUMNS = ["median", *names.AGREEMENT_COLUMNS, "agrees"]
# What a configuration is but for its precision, and, where the f16 run has
# no twin of its own lane count (f16 may pack twice the lanes), but for its lanes too.
TWIN_KEYS = [k for k in names.CONFIG_KEYS if k != names.PRECISION]
LOOSE_TWIN_KEYS = [k for k in TWIN_KEYS if k not in (names.LANES, names.SIMD_TARGET)]


def side_column(precision: str, column: str) -> str:
    """The column of one precision's side: f32_median, f16_psnr_db, ..."""
    return f"{precision}_{column}"


COLUMNS = [
    *names.CONFIG_KEYS,
    *(side_column(p, c) for p in (names.F32, names.F16) for c in SIDE_COLUMNS),
    SPEEDUP,
    SPEEDUP_LOW,
    SPEEDUP_HIGH,
]


def agrees(within: float, psnr_db: float) -> float:
    """1.0 where an image agrees with the reference under section 8's rule,
    0.0 where it does not, NaN where its run had no --agreement."""
    if not (math.isfinite(within) and not math.isnan(psnr_db)):
        return math.nan
    return float(within >= AGREES_WITHIN and psnr_db >= AGREES_PSNR_DB)


def agreement_by_config(frames: pd.DataFrame) -> dict[tuple[str, ...], dict[str, float]]:
    """Each configuration's agreement (AGREEMENT_COLUMNS and agrees), by its
    CONFIG_KEYS as strings: the median over its runs (one image of frame 0
    per run, the same in each)."""
    runs = frames.drop_duplicates(names.RUN_ID)
    out = {}
    for key, group in runs.groupby(names.CONFIG_KEYS, sort=False, dropna=False):
        values = {c: _median(group[c]) for c in names.AGREEMENT_COLUMNS}
        values["agrees"] = agrees(values[names.WITHIN_TOLERANCE], values[names.PSNR_DB])
        out[tuple(str(k) for k in key)] = values
    return out


def _median(values: pd.Series) -> float:
    """The median of the values that are there (inf counts: identical images); NaN where none are."""
    present = values.dropna()
    return float(present.median()) if len(present) else math.nan


def f32_twin(summary: pd.DataFrame, row: pd.Series) -> pd.Series | None:
    """The f32 configuration an f16 one is measured against: the same in
    every key but the precision; where none ran, the same but for lanes
    and SIMD target, the widest of them."""
    f32 = names.at_f32(summary)
    for keys in (TWIN_KEYS, LOOSE_TWIN_KEYS):
        hit = f32[(f32[keys].astype(str) == row[keys].astype(str)).all(axis=1)]
        if not hit.empty:
            return hit.sort_values(names.LANES, ascending=False, kind="stable").iloc[0]
    return None


def half_precision(summary: pd.DataFrame, frames: pd.DataFrame) -> pd.DataFrame:
    """One row per f16 configuration: its keys, each side's median and
    agreement, and the speedup f32/f16 with its 95 % bootstrap CI (NaN
    where its f32 twin did not run). Empty for a run without f16."""
    halves = summary[summary[names.PRECISION] == names.F16]
    if halves.empty:
        return pd.DataFrame(columns=COLUMNS)
    samples, agreement = stats.samples_by_config(frames), agreement_by_config(frames)
    rows = []
    for _, half in halves.iterrows():
        twin = f32_twin(summary, half)
        row = {k: half[k] for k in names.CONFIG_KEYS}
        for precision, side in ((names.F32, twin), (names.F16, half)):
            row.update(_side(precision, side, agreement))
        empty = stats.finite([])
        f32_times = samples.get(stats.config_key(twin), empty) if twin is not None else empty
        ratio, low, high = stats.median_ratio_ci(f32_times, samples.get(stats.config_key(half), empty))
        rows.append({**row, SPEEDUP: ratio, SPEEDUP_LOW: low, SPEEDUP_HIGH: high})
    return pd.DataFrame(rows, columns=COLUMNS)


def _side(precision: str, row: pd.Series | None, agreement: dict) -> dict[str, float]:
    values = dict.fromkeys(SIDE_COLUMNS, math.nan)
    if row is not None:
        values = {"median": row["median"], **agreement.get(stats.config_key(row), values)}
    return {side_column(precision, c): values.get(c, math.nan) for c in SIDE_COLUMNS}


def refused(manifests: list[dict | None]) -> dict[str, str]:
    """Renderer -> what its probe at a precision other than f32 said, where
    the bench skipped those runs (the binary refuses --precision f16 without
    native f16 arithmetic: the CPU's Highway target, the device's shaderFloat16)."""
    out: dict[str, str] = {}
    for m in manifests:
        configs = {c.get("id"): c for c in (m or {}).get("configs", [])}
        for r in (m or {}).get("runs", []):
            config = configs.get(r.get("config")) or {}
            if r.get("status") == RunStatus.UNAVAILABLE and names.precision_of(config.get("precision")) != names.F32:
                out.setdefault(r.get("renderer", "?"), probe_reason(r))
    return out


# --- the table ---------------------------------------------------------------------

TITLE = "Half precision (the thesis' ablation)"
SLUG = "half-precision"


HEADERS = [
    "scene",
    "stage",
    "renderer",
    "configuration",
    "f32 ms",
    "f16 ms",
    "f32/f16 [95% CI]",
    "f32 image",
    "f16 image",
]


def half_precision_table(table: pd.DataFrame, refusals: dict[str, str]) -> tables.Table:
    """Per scene, stage and renderer with f16 data: both medians, the speedup
    f32/f16 with its CI, and each image's agreement with the double reference."""
    rows = []
    for _, r in table.iterrows():
        rows.append(
            [
                r[names.SCENE],
                r[names.STAGE],
                r[names.RENDERER],
                configuration_text(r),
                tables.fmt_ms(r[side_column(names.F32, "median")]),
                tables.fmt_ms(r[side_column(names.F16, "median")]),
                _ratio(r[SPEEDUP], r[SPEEDUP_LOW], r[SPEEDUP_HIGH]),
                *(agreement_text(r, p) for p in (names.F32, names.F16)),
            ]
        )
    rows += [
        [tables.MISSING, tables.MISSING, renderer, "f16 refused", *[tables.MISSING] * 3, "", reason]
        for renderer, reason in refusals.items()
    ]
    return tables.Table(SLUG, TITLE, HEADERS, rows, "llllrrrll", [NOTE])


NOTE = (
    "Median render_ms of the measured frames at each precision; f32/f16 = the f32 median over the f16 one (> 1: "
    "half precision is faster), its 95% CI from resampling each side's frames (2000 times, seeded). Image: frame "
    "0 against the double-precision reference (--agreement): the share of pixels within 2/255, PSNR, the largest "
    "channel difference, and whether it agrees under the render model's rule (docs/render-model.md section 8: "
    f">= {AGREES_WITHIN:.1%} within and >= {AGREES_PSNR_DB:g} dB); {tables.MISSING} where the run had no "
    "--agreement. f16 refused: the bench's probe of the renderer at --precision f16 failed, with what it said."
)


def configuration_text(row) -> str:
    """'16 lanes AVX3', 'bvh wide' ...: the configuration but for its scene,
    stage, renderer and precision (the accel where it is not brute force)."""
    accel = [row[names.ACCEL]] if row[names.ACCEL] != names.BRUTE_FORCE else []
    return " ".join([tables.describe_config(row), *accel, *names.walk_tag(row)]).strip()


def _ratio(value: float, low: float, high: float) -> str:
    text = tables.fmt_fixed(value, 2)
    return text if not math.isfinite(low) else f"{text} [{tables.fmt_fixed(low, 2)}, {tables.fmt_fixed(high, 2)}]"


def agreement_text(row, precision: str) -> str:
    """'99.8%, 52.1 dB, max 7: agrees'; tables.MISSING without --agreement."""
    within = row[side_column(precision, names.WITHIN_TOLERANCE)]
    if not math.isfinite(within):
        return tables.MISSING
    psnr = row[side_column(precision, names.PSNR_DB)]
    psnr_text = "identical" if psnr == math.inf else f"{psnr:.1f} dB"
    worst = tables.fmt_int(row[side_column(precision, names.MAX_CHANNEL_DIFFERENCE)])
    verdict = "agrees" if row[side_column(precision, "agrees")] == 1.0 else "fails"
    return f"{tables.fmt_percent(within)}, {psnr_text}, max {worst}: {verdict}"
