"""Summary statistics of frame times: pure functions over arrays and frames.

Frame times are skewed (a frame can be slow, never faster than the work), so
the report leads with the median and the median absolute deviation; mean and
standard deviation are kept for comparison with the thesis, which reported
means. Outliers are flagged by the modified z-score (Iglewicz & Hoaglin),
never dropped.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from rtbench import names

# Iglewicz & Hoaglin: |M| > 3.5 marks a potential outlier; 0.6745 is the
# 0.75 quantile of the standard normal, making MAD comparable to sigma.
OUTLIER_LIMIT = 3.5
MAD_TO_Z = 0.6745
BOOTSTRAP_RESAMPLES = 2000
BOOTSTRAP_SEED = 20240601
CONFIDENCE = 0.95

CONFIG_KEYS = names.CONFIG_KEYS


def finite(values) -> np.ndarray:
    """The finite values, as floats."""
    x = np.asarray(values, dtype=float)
    return x[np.isfinite(x)]


def resampled_medians(x: np.ndarray, rng: np.random.Generator, resamples: int = BOOTSTRAP_RESAMPLES) -> np.ndarray:
    """The medians of `resamples` bootstrap resamples of `x` (with replacement)."""
    return np.median(x[rng.integers(0, x.size, size=(resamples, x.size))], axis=1)


def percentile_interval(samples: np.ndarray, confidence: float = CONFIDENCE) -> tuple[float, float]:
    """The central `confidence` interval of bootstrap `samples`."""
    tail = (1.0 - confidence) / 2.0 * 100.0
    lo, hi = np.percentile(samples, [tail, 100.0 - tail])
    return (float(lo), float(hi))


def median_ratio_ci(
    numerator, denominator, seed: int = BOOTSTRAP_SEED, resamples: int = BOOTSTRAP_RESAMPLES
) -> tuple[float, float, float]:
    """median(numerator) / median(denominator) (a speedup: the slower side's
    times over the faster one's) and its percentile-bootstrap CI: each side's
    values resampled on their own, the ratio of each resample's medians.
    NaN where either side is empty. Seeded, numerator first, as
    findings.figure_ci resamples a two-configuration figure."""
    a, b = finite(numerator), finite(denominator)
    if a.size == 0 or b.size == 0:
        return math.nan, math.nan, math.nan
    rng = np.random.default_rng(seed)
    ratios = resampled_medians(a, rng, resamples) / resampled_medians(b, rng, resamples)
    low, high = percentile_interval(ratios)
    return float(np.median(a) / np.median(b)), low, high


def median(values) -> float:
    x = finite(values)
    return float(np.median(x)) if x.size else math.nan


def mad(values) -> float:
    """Median absolute deviation from the median (raw, not scaled to sigma)."""
    x = finite(values)
    return float(np.median(np.abs(x - np.median(x)))) if x.size else math.nan


def percentile(values, q: float) -> float:
    """The q-th percentile with linear interpolation (numpy's default)."""
    x = finite(values)
    return float(np.percentile(x, q)) if x.size else math.nan


def bootstrap_median_ci(
    values, confidence: float = CONFIDENCE, resamples: int = BOOTSTRAP_RESAMPLES, seed: int = BOOTSTRAP_SEED
) -> tuple[float, float]:
    """Percentile-bootstrap confidence interval of the median. Seeded, so the
    same data always give the same interval (reports are reproducible)."""
    x = finite(values)
    if x.size == 0:
        return (math.nan, math.nan)
    if x.size == 1:
        return (float(x[0]), float(x[0]))
    return percentile_interval(resampled_medians(x, np.random.default_rng(seed), resamples), confidence)


def modified_z_scores(values) -> np.ndarray:
    """M_i = 0.6745 (x_i - median) / MAD. With MAD = 0 (more than half the
    values identical) every value off the median gets an infinite score."""
    x = np.asarray(values, dtype=float)
    finite = x[np.isfinite(x)]
    if finite.size == 0:
        return np.full(x.shape, np.nan)
    center = np.median(finite)
    spread = np.median(np.abs(finite - center))
    deviation = x - center
    if spread == 0:
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(deviation == 0, 0.0, np.sign(deviation) * np.inf)
    return MAD_TO_Z * deviation / spread


def outlier_mask(values, limit: float = OUTLIER_LIMIT) -> np.ndarray:
    """True where |modified z-score| > limit."""
    return np.abs(modified_z_scores(values)) > limit


def summarize(values, seed: int = BOOTSTRAP_SEED) -> dict[str, float]:
    """Every statistic the report shows for one set of frame times."""
    x = finite(values)
    lo, hi = bootstrap_median_ci(x, seed=seed)
    return {
        "n": int(x.size),
        "median": median(x),
        "mean": float(x.mean()) if x.size else math.nan,
        "std": float(x.std(ddof=1)) if x.size > 1 else math.nan,
        "mad": mad(x),
        "ci_low": lo,
        "ci_high": hi,
        "p95": percentile(x, 95),
        "p99": percentile(x, 99),
        "min": float(x.min()) if x.size else math.nan,
        "max": float(x.max()) if x.size else math.nan,
        "outliers": int(outlier_mask(x).sum()) if x.size else 0,
    }


def measured(frames: pd.DataFrame) -> pd.DataFrame:
    """The measured frames only: warm-up frames never enter a statistic."""
    return frames[frames[names.WARMUP] == 0]


def config_key(row) -> tuple[str, ...]:
    """A configuration's CONFIG_KEYS as strings: the key of samples_by_config."""
    return tuple(str(row[k]) for k in names.CONFIG_KEYS)


def samples_by_config(frames: pd.DataFrame) -> dict[tuple[str, ...], np.ndarray]:
    """Each configuration's finite measured render times, by config_key."""
    groups = measured(frames).groupby(names.CONFIG_KEYS, sort=False, dropna=False)
    return {tuple(str(k) for k in key): finite(g[names.RENDER_MS].to_numpy()) for key, g in groups}


def modified_z_by_config(frames: pd.DataFrame, value: str = names.RENDER_MS) -> pd.Series:
    """Modified z-score of each measured frame within its configuration (all
    repetitions pooled, as in the summary); NaN for warm-up frames."""
    scores = pd.Series(np.nan, index=frames.index)
    for _, group in measured(frames).groupby(CONFIG_KEYS, sort=False, dropna=False):
        scores.loc[group.index] = modified_z_scores(group[value].to_numpy())
    return scores


def flag_outliers(frames: pd.DataFrame, value: str = names.RENDER_MS) -> pd.Series:
    """Per configuration, which measured frames are outliers (warm-up: False)."""
    return modified_z_by_config(frames, value).abs() > OUTLIER_LIMIT


def summarize_configs(frames: pd.DataFrame, value: str = names.RENDER_MS) -> pd.DataFrame:
    """One row per configuration: statistics of `value` over the measured frames
    of all its repetitions pooled, plus the spread between repetitions (the
    coefficient of variation of the per-repetition medians)."""
    rows = []
    meas = measured(frames)
    for key, group in meas.groupby(CONFIG_KEYS, sort=False, dropna=False):
        row = dict(zip(CONFIG_KEYS, key))
        row.update(summarize(group[value].to_numpy()))
        rep_medians = group.groupby(names.REPETITION)[value].median().to_numpy()
        row["repetitions"] = len(rep_medians)
        row["rep_spread"] = coefficient_of_variation(rep_medians)
        rows.append(row)
    columns = [
        *CONFIG_KEYS,
        "n",
        "median",
        "mean",
        "std",
        "mad",
        "ci_low",
        "ci_high",
        "p95",
        "p99",
        "min",
        "max",
        "outliers",
        "repetitions",
        "rep_spread",
    ]
    summary = pd.DataFrame(rows, columns=columns)
    return sort_configs(summary)


def coefficient_of_variation(values) -> float:
    """Sample standard deviation / mean; NaN for fewer than two values."""
    x = finite(values)
    if x.size < 2 or x.mean() == 0:
        return math.nan
    return float(x.std(ddof=1) / x.mean())


def config_label(row) -> str:
    """scene/renderer/stage[/tN][/lN][/accel[/traversal][/gpu variants]][/f16]: a
    configuration's name in warnings, with the threads and lanes where its
    renderer takes them, the accel where it is not brute force, the traversal
    where it is not packets and the GPU variants where they are not the
    defaults, the precision where it is not f32 (names.accel_tag)."""
    options = "".join(f"/{option[0]}{value}" for option, value in names.label_options(row))
    accel = "".join(f"/{tag}" for tag in names.accel_tag(row))
    return f"{row[names.SCENE]}/{row[names.RENDERER]}/{row[names.STAGE]}{options}{accel}"


def sort_configs(df: pd.DataFrame) -> pd.DataFrame:
    """Stage, scene, renderer, accel, traversal, the GPU variants, the
    precision (schema order where the schema has one), threads, lanes."""
    gpu = {f"_{axis}": df[axis].map(lambda v, a=axis: names.gpu_order(a, v)) for axis in names.GPU_AXES}
    key = df.assign(
        _stage=df[names.STAGE].map(names.stage_order),
        _renderer=df[names.RENDERER].map(names.renderer_order),
        _accel=df[names.ACCEL].map(names.accel_order),
        _traversal=df[names.TRAVERSAL].map(names.traversal_order),
        **gpu,
        _precision=df[names.PRECISION].map(names.precision_order),
    )
    helpers = ["_stage", "_renderer", "_accel", "_traversal", *gpu, "_precision"]
    order = ["_stage", names.SCENE, "_renderer", "_accel", "_traversal", *gpu, "_precision"]
    order += [names.THREADS, names.LANES, names.WIDTH]
    key = key.sort_values(order, kind="stable")
    return key.drop(columns=helpers).reset_index(drop=True)
