"""The comparison of two sets of benchmark runs, as data and pure functions:
configurations matched between BASE and NEW, the statistics of each pair
(medians, the ratio with its bootstrap interval, the Mann-Whitney U test,
the verdict), the frame-budget statistics of both sides and the
environment facts that differ. Nothing here reads or writes a file:
rtbench.compare_input loads the two sides, rtbench.compare_output writes
what this computes, rtbench.compare_cli is the command (scripts/compare.py,
whose --help says what the comparison does).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd
from scipy import stats as scipy_stats

from rtbench import budget, names, noise, stats

FASTER, SLOWER, SAME = "faster", "slower", "~"
DEFAULT_ALPHA = 0.05
# Below this relative change a difference is not called, however significant:
# the spread between repetitions of one configuration that noise.py warns at.
DEFAULT_NOISE = noise.SPREAD_LIMIT
# What the machine decides rather than the benchmark: left out of the match
# key by default and listed among the environment differences instead.
ENVIRONMENT_KEYS = (names.DEVICE, names.SIMD_TARGET)
# With --all-cores, the match key's threads: "all" where a configuration ran
# on every logical core of its machine, else the thread count.
MATCH_THREADS = "match_threads"
ALL_CORES = "all"


class CompareError(ValueError):
    """Input that cannot be compared; the message names the runs or file."""


@dataclass(frozen=True)
class Options:
    alpha: float = DEFAULT_ALPHA
    noise: float = DEFAULT_NOISE
    fail_above: float | None = None
    budgets_ms: tuple[float, ...] = budget.DEFAULT_BUDGETS_MS
    all_cores: bool = False
    key_with: tuple[str, ...] = ()


@dataclass
class Side:
    """One side of the comparison: its runs pooled."""

    name: str  # "base" or "new"
    paths: list[Path]  # as given (directories or archives)
    run_names: list[str]  # the run directories' names
    frames: pd.DataFrame
    environment: dict[str, list[str]]  # fact -> its distinct values over every run


@dataclass
class Comparison:
    base: Side
    new: Side
    options: Options
    rows: pd.DataFrame  # one per configuration on both sides (see compare_sides)
    only_base: list[str]
    only_new: list[str]
    geomean: float
    differences: list[tuple[str, list[str], list[str]]] = field(default_factory=list)

    def verdict_counts(self) -> dict[str, int]:
        counts = self.rows["verdict"].value_counts() if len(self.rows) else {}
        return {v: int(counts.get(v, 0)) for v in (FASTER, SLOWER, SAME)}

    def failures(self) -> list[str]:
        """Configurations significantly slower by more than --fail-above."""
        limit = self.options.fail_above
        if limit is None or self.rows.empty:
            return []
        bad = self.rows[(self.rows["verdict"] == SLOWER) & (self.rows["ratio"] > 1.0 + limit)]
        return list(bad["label"])


# --- statistics: pure functions ------------------------------------------------


def ratio_ci(
    base,
    new,
    confidence: float = stats.CONFIDENCE,
    resamples: int = stats.BOOTSTRAP_RESAMPLES,
    seed: int = stats.BOOTSTRAP_SEED,
) -> tuple[float, float]:
    """Percentile-bootstrap CI of median(new) / median(base), each side
    resampled on its own; seeded, so the same data give the same interval."""
    b, n = stats.finite(base), stats.finite(new)
    if b.size == 0 or n.size == 0:
        return (math.nan, math.nan)
    rng = np.random.default_rng(seed)  # one generator: base's resamples, then new's
    base_medians = stats.resampled_medians(b, rng, resamples)
    new_medians = stats.resampled_medians(n, rng, resamples)
    with np.errstate(divide="ignore", invalid="ignore"):
        return stats.percentile_interval(new_medians / base_medians, confidence)


def mann_whitney_p(base, new) -> float:
    """Two-sided Mann-Whitney U test p-value; 1 where the two sets cannot be
    told apart at all (every value equal), NaN without data."""
    b, n = stats.finite(base), stats.finite(new)
    if b.size == 0 or n.size == 0:
        return math.nan
    if np.ptp(np.concatenate([b, n])) == 0:
        return 1.0
    return float(scipy_stats.mannwhitneyu(b, n, alternative="two-sided").pvalue)


def verdict(ratio: float, ci: tuple[float, float], p: float, alpha: float, noise_limit: float) -> str:
    """faster / slower when the change is significant by every test, else ~."""
    lo, hi = ci
    if not (math.isfinite(ratio) and math.isfinite(p) and p < alpha):
        return SAME
    if not (math.isfinite(lo) and math.isfinite(hi)) or lo <= 1.0 <= hi or abs(ratio - 1.0) < noise_limit:
        return SAME
    return FASTER if ratio < 1.0 else SLOWER


def geometric_mean(ratios) -> float:
    x = stats.finite(ratios)
    x = x[x > 0]
    # math.log and math.fsum, not np.log: NumPy 2's vectorised log rounds the
    # last bit otherwise than NumPy 1.24's, and compare.json holds the mean at
    # full precision.
    return math.exp(math.fsum(math.log(v) for v in x) / x.size) if x.size else math.nan


def compare_values(base, new, options: Options) -> dict:
    """Medians, ratio, its CI, the U test's p and the verdict of one configuration."""
    mb, mn = stats.median(base), stats.median(new)
    ratio = mn / mb if mb > 0 and math.isfinite(mn) else math.nan
    ci = ratio_ci(base, new)
    p = mann_whitney_p(base, new)
    return {
        "base_n": int(stats.finite(base).size),
        "new_n": int(stats.finite(new).size),
        "base_median": mb,
        "new_median": mn,
        "ratio": ratio,
        "ci_low": ci[0],
        "ci_high": ci[1],
        "p_value": p,
        "verdict": verdict(ratio, ci, p, options.alpha, options.noise),
    }


# --- matching --------------------------------------------------------------------


def match_keys(options: Options) -> list[str]:
    """The columns two configurations must agree on to be compared."""
    keys = [k for k in stats.CONFIG_KEYS if k not in ENVIRONMENT_KEYS or k in options.key_with]
    if options.all_cores:
        keys = [MATCH_THREADS if k == names.THREADS else k for k in keys]
    return keys


def with_match_columns(frames: pd.DataFrame, options: Options) -> pd.DataFrame:
    if not options.all_cores:
        return frames
    every_core = frames[names.THREADS] == frames[names.LOGICAL_CORES]
    takes_threads = frames[names.RENDERER].map(lambda r: names.accepts(r, names.THREADS))
    threads = frames[names.THREADS].astype(str).where(~(every_core & takes_threads), ALL_CORES)
    return frames.assign(**{MATCH_THREADS: threads})


def configurations(side: Side, keys: list[str]) -> dict[tuple, pd.DataFrame]:
    """Match key -> that configuration's measured frames; a CompareError where
    one key covers configurations that differ in a column left out of it."""
    out = {}
    for key, group in stats.measured(side.frames).groupby(keys, sort=False, dropna=False):
        full = group[stats.CONFIG_KEYS].drop_duplicates()
        if len(full) > 1:
            column = next(c for c in stats.CONFIG_KEYS if full[c].nunique(dropna=False) > 1)
            values = ", ".join(sorted(map(str, full[column].unique())))
            raise CompareError(
                f"{', '.join(map(str, side.paths))}: configuration {stats.config_label(full.iloc[0])} ran with more "
                f"than one {column} ({values}); compare them separately, or match on it with --key-with {column}"
            )
        out[key if isinstance(key, tuple) else (key,)] = group
    return out


def label(base_row, new_row, show_size: bool) -> str:
    """scene/renderer/stage/tN/lN[/accel][/WxH]; an option that differs
    between the sides (threads under --all-cores) as 'base→new'."""
    options = ""
    for option, value in names.label_options(base_row):
        other = new_row[option]
        options += f"/{option[0]}{value}" + (f"→{other}" if other != value else "")
    accel = "".join(f"/{tag}" for tag in names.accel_tag(base_row))
    size = f"/{base_row[names.WIDTH]}x{base_row[names.HEIGHT]}" if show_size else ""
    return f"{base_row[names.SCENE]}/{base_row[names.RENDERER]}/{base_row[names.STAGE]}{options}{accel}{size}"


def frame_budget(side: str, group: pd.DataFrame, budgets_ms) -> dict:
    """The frame-budget statistics of one side's frames of a configuration,
    each under `side`_frame_ (base_frame_p99, ...)."""
    series = budget.runs_in_order(group.assign(**{budget.FRAME_MS: budget.frame_ms(group)}))
    return {f"{side}_frame_{k}": v for k, v in budget.budget_stats(series, budgets_ms).items() if k != "n"}


def compare_sides(base: Side, new: Side, options: Options) -> Comparison:
    """Every statistic of the comparison; no I/O."""
    keys = match_keys(options)
    base.frames, new.frames = with_match_columns(base.frames, options), with_match_columns(new.frames, options)
    ours, theirs = configurations(base, keys), configurations(new, keys)
    both = [k for k in ours if k in theirs]
    sizes = {(g[names.WIDTH].iloc[0], g[names.HEIGHT].iloc[0]) for g in [*ours.values(), *theirs.values()]}
    rows = []
    for key in both:
        b, n = ours[key], theirs[key]
        row = {
            **dict(zip(stats.CONFIG_KEYS, b[stats.CONFIG_KEYS].iloc[0])),
            "label": label(b.iloc[0], n.iloc[0], len(sizes) > 1),
            **compare_values(b[names.RENDER_MS], n[names.RENDER_MS], options),
        }
        for side, group in (("base", b), ("new", n)):
            row.update(frame_budget(side, group, options.budgets_ms))
        rows.append(row)
    table = stats.sort_configs(pd.DataFrame(rows)) if rows else pd.DataFrame(columns=["label", "verdict", "ratio"])
    only = [
        [label(g.iloc[0], g.iloc[0], len(sizes) > 1) for k, g in side.items() if k not in other]
        for side, other in ((ours, theirs), (theirs, ours))
    ]
    return Comparison(
        base,
        new,
        options,
        table,
        sorted(only[0]),
        sorted(only[1]),
        geometric_mean(table["ratio"]) if len(table) else math.nan,
        environment_differences(base.environment, new.environment),
    )


# --- environment -------------------------------------------------------------------


def _device_driver(device: dict) -> str | None:
    driver = (names.META_DEVICE_DRIVER_NAME, names.META_DEVICE_DRIVER_VERSION)
    text = " ".join(str(device.get(k) or "") for k in driver).strip()
    info = device.get(names.META_DEVICE_DRIVER_INFO)
    return f"{text} ({info})" if info and info not in text else text or None


def _git(build: dict) -> str | None:
    commit = build.get(names.GIT_COMMIT)
    if not commit:
        return None
    return str(commit)[:12] + (" (dirty)" if build.get(names.GIT_DIRTY) else "")


def _nix(build: dict) -> str:
    nix = build.get(names.META_BUILD_NIX)
    return f"yes (nixpkgs {nix.get(names.META_NIXPKGS_REV, 'unknown')})" if isinstance(nix, dict) else "no"


# The facts read from each run's metadata sidecar: (name, value of a sidecar).
METADATA_FACTS = [
    ("CPU", lambda m: (m.get(names.META_HOST) or {}).get(names.CPU_MODEL)),
    ("logical cores", lambda m: (m.get(names.META_HOST) or {}).get(names.LOGICAL_CORES)),
    ("OS", lambda m: (m.get(names.META_HOST) or {}).get(names.META_HOST_OS)),
    ("kernel", lambda m: (m.get(names.META_HOST) or {}).get(names.META_HOST_KERNEL)),
    ("compiler", lambda m: (m.get(names.META_BUILD) or {}).get(names.META_BUILD_COMPILER)),
    ("compiler flags", lambda m: (m.get(names.META_BUILD) or {}).get(names.META_BUILD_COMPILER_FLAGS)),
    ("build type", lambda m: (m.get(names.META_BUILD) or {}).get(names.BUILD_TYPE)),
    ("version", lambda m: (m.get(names.META_BUILD) or {}).get(names.META_BUILD_VERSION)),
    ("git commit", lambda m: _git(m.get(names.META_BUILD) or {})),
    ("Nix", lambda m: _nix(m.get(names.META_BUILD) or {})),
    ("SIMD target", lambda m: (m.get(names.META_CONFIG) or {}).get(names.META_CONFIG_SIMD_TARGET) or None),
    ("Vulkan device", lambda m: (m.get(names.META_DEVICE) or {}).get(names.META_DEVICE_NAME)),
    ("Vulkan driver", lambda m: _device_driver(m.get(names.META_DEVICE) or {})),
    ("Vulkan API", lambda m: (m.get(names.META_DEVICE) or {}).get(names.META_DEVICE_API_VERSION)),
]


def environment(runs: Iterable[tuple[dict, list[dict]]]) -> dict[str, list[str]]:
    """Every fact of METADATA_FACTS, each library's version and the CPU
    governors of the runner's manifest: fact -> distinct values, sorted.
    `runs`: (manifest, metadata sidecars of its finished runs) of each run
    directory, as rtbench.compare_input reads them."""
    facts: dict[str, set[str]] = {}

    def add(fact: str, value) -> None:
        if value is not None and value != "":
            facts.setdefault(fact, set()).add(str(value))

    for manifest, metas in runs:
        for governor in (manifest.get("host") or {}).get("cpu_governors") or []:
            add("CPU governor", governor)
        for meta in metas:
            for fact, read in METADATA_FACTS:
                add(fact, read(meta))
            for library, version in sorted((meta.get(names.META_LIBRARIES) or {}).items()):
                add(f"library {library}", version)
    return {fact: sorted(values) for fact, values in facts.items()}


def environment_differences(
    base: dict[str, list[str]], new: dict[str, list[str]]
) -> list[tuple[str, list[str], list[str]]]:
    """(fact, base values, new values) of every fact whose values differ, in
    METADATA_FACTS order, then the rest by name."""
    order = [fact for fact, _ in METADATA_FACTS]
    facts = sorted(set(base) | set(new), key=lambda f: (order.index(f) if f in order else len(order), f))
    return [(f, base.get(f, []), new.get(f, [])) for f in facts if base.get(f, []) != new.get(f, [])]
