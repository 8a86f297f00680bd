"""The thesis' findings, checked: each claim of docs/thesis.md ("What the
tables show", "Conclusion") as a predicate over a run's data, with a verdict.

A claim names the configurations it needs (scene, renderer, stage; threads,
lanes and GPU variant as the report's headline rows choose them), a figure
computed from their median render times, and the region of that figure in
which the claim holds. Its verdict:

- `reproduced`: the figure's 95 % bootstrap CI lies inside the region;
- `not reproduced`: the CI lies wholly outside it;
- `inconclusive`: the CI straddles a border of the region;
- `not measured`: a configuration the figure needs is not in the run (the
  row names which, or what refused it: half precision on a CPU without
  native f16 arithmetic).

Claim 8 (half precision) joins two parts, the speedup f32/f16 and the f16
image's agreement with the double-precision reference (precision.py); its
verdict is both's (both_hold), and row 8b, the kit's extension, asks the
same of the GPU renderer.

The figure's CI resamples each configuration's measured frames (seeded, as
stats.bootstrap_median_ci) and evaluates the figure on every resample's
medians: a CI of the figure itself, not the conservative range of
metrics_table. The lines chosen ("about", "same regime") are documented in
docs/thesis.md, "The findings, checked"; they live here only, in CLAIMS.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pandas as pd

from rtbench import metrics, names, precision, stats, tables

REPRODUCED = "reproduced"
NOT_REPRODUCED = "not reproduced"
INCONCLUSIVE = "inconclusive"
NOT_MEASURED = "not measured"
VERDICTS = (REPRODUCED, NOT_REPRODUCED, INCONCLUSIVE, NOT_MEASURED)

# "About x" in the thesis' text: within a factor ABOUT of x. The thesis gives
# one mean per figure, at -O0 on another machine; a factor 1.5 keeps its
# 1.6x apart from the 2.5x and more that a "modest" speedup would not be.
ABOUT = 1.5
# "Three orders of magnitude": the figure's log10 within 3 +- 0.5.
ORDERS = 3.0
# Karp-Flatt regimes (docs/thesis.md "The findings, checked"): below
# NEAR_ZERO_E the work is as good as perfectly parallel (the thesis' GPU:
# 0.002 stated, 0.00003 from its table); at SERIAL_E and above a large share
# of it behaves as serial (the thesis' SIMD: 0.206 stated, 0.141 from its
# table). Both thesis values of each renderer fall in the same regime, so the
# verdict does not hang on the thesis' miscomputed e.
NEAR_ZERO_E = 0.01
SERIAL_E = 0.1

# The thesis' machine (docs/thesis.md "Measurement"): 8 cores of two kinds,
# 128-bit NEON (4 float lanes), -O0; its Karp-Flatt p per renderer.
THESIS_CORES = "8 cores (4 performance + 4 efficiency, Apple M1)"
THESIS_THREADS = 8
THESIS_LANES = 4
THESIS_OPT = "-O0"
THESIS_P = {"tbb_only": 8, "simd_only": 4, "simd_tbb": 32, "gpu": 1024}

SCENE = "random100"
SIMD_RENDERERS = ("simd_tbb", "simd_only")
SCALAR_RENDERERS = ("sequential", "tbb_only")
CPU_RENDERERS = ("sequential", "simd_tbb", "simd_only", "tbb_only")

# Why ours may differ from the thesis: the factors the reason column checks.
BUILD, CORES, LANES, OCCUPANCY = "build", "cores", "lanes", "occupancy"


@dataclass(frozen=True)
class Ref:
    """One configuration a claim needs: renderer and stage at the claim's scene."""

    renderer: str
    stage: str

    @property
    def key(self) -> str:
        return f"{self.renderer}@{self.stage}"


# A figure from the medians (arrays: point estimate or bootstrap resamples)
# and p of each Ref.key.
Figure = Callable[[dict, dict], object]


@dataclass(frozen=True)
class Claim:
    key: str
    text: str  # the thesis' claim, in our words
    figure: str  # what is computed
    refs: tuple[Ref, ...]
    compute: Figure
    low: float  # the region in which the claim holds: low <= figure <= high
    high: float
    line: str  # the region, as the table says it
    factors: tuple[str, ...] = ()  # what the reason column looks at
    stated: tuple[str, str] | None = None  # (metric, renderer): the thesis' stated value, metrics_reported.csv
    scene: str = SCENE


def _s(m: dict, ref: Ref, over: Ref) -> object:
    """Speedup of `ref` over `over`, from their medians."""
    return m[over.key] / m[ref.key]


def _kf(s, p: float):
    return (1.0 / s - 1.0 / p) / (1.0 - 1.0 / p)


def _r(renderer: str, stage: str) -> Ref:
    return Ref(renderer, stage)


SEQ_O, SEQ_P = _r("sequential", "original"), _r("sequential", "optimized")


def _speedup(
    key: str,
    text: str,
    renderer: str,
    stage: str,
    region: tuple[float, float],
    line: str,
    factors: tuple[str, ...],
    stated: tuple[str, str] | None = None,
) -> Claim:
    """A claim on the speedup of `renderer` over sequential at `stage`:
    S = T(sequential) / T(renderer), in `region` (low, high)."""
    seq, ref = _r("sequential", stage), _r(renderer, stage)
    return Claim(
        key,
        text,
        f"S = T(sequential) / T({renderer})",
        (seq, ref),
        lambda m, p: _s(m, ref, seq),
        *region,
        line,
        factors,
        stated,
    )


def _karp_flatt(
    key: str, text: str, renderer: str, p_is: str, region: tuple[float, float], line: str, factors: tuple[str, ...]
) -> Claim:
    """A claim on the Karp-Flatt serial fraction e of `renderer` (optimized),
    from its speedup over sequential and its p (`p_is` says what p is)."""
    ref = _r(renderer, "optimized")
    return Claim(
        key,
        text,
        f"Karp-Flatt e of {renderer}, p = {p_is}",
        (SEQ_P, ref),
        lambda m, p: _kf(_s(m, ref, SEQ_P), p[ref.key]),
        *region,
        line,
        factors,
        ("karp_flatt", renderer),
    )


def _gains(m: dict, renderers) -> list:
    return [m[f"{r}@original"] / m[f"{r}@single-pass"] for r in renderers]


def _min(values: list):
    return np.minimum.reduce(values) if isinstance(values[0], np.ndarray) else min(values)


def _max(values: list):
    return np.maximum.reduce(values) if isinstance(values[0], np.ndarray) else max(values)


# The thesis' figures in the claims' own words (docs/thesis.md "What the tables
# show"): 1.6x of SIMD + TBB; TBB only's 4.25-4.53x over 8 cores, i.e. a
# parallel efficiency of 0.53-0.57; the region of each is set around them.
CLAIMS: list[Claim] = [
    _speedup(
        "1",
        "SIMD + TBB gives only about 1.6x over sequential (original)",
        "simd_tbb",
        "original",
        (1.6 / ABOUT, 1.6 * ABOUT),
        f"about 1.6x: S in [1.6/{ABOUT:g}, 1.6×{ABOUT:g}]",
        (BUILD, CORES, LANES, OCCUPANCY),
    ),
    Claim(
        "2",
        "threads alone (TBB only) give about 4.2x on 8 cores (original), scaled to our cores",
        "S / p = T(sequential) / T(tbb_only) / threads",
        (SEQ_O, _r("tbb_only", "original")),
        lambda m, p: _s(m, _r("tbb_only", "original"), SEQ_O) / p["tbb_only@original"],
        0.53 / ABOUT,
        min(0.57 * ABOUT, 1.0),
        f"parallel efficiency about the thesis' 0.53-0.57: S/p in [0.53/{ABOUT:g}, min(0.57×{ABOUT:g}, 1)]",
        (BUILD, CORES),
    ),
    _speedup(
        "3",
        "SIMD alone is slower than sequential (original; thesis 3.0-3.5x slower)",
        "simd_only",
        "original",
        (0.0, 1.0),
        "slower: S < 1",
        (BUILD, LANES, OCCUPANCY),
    ),
    Claim(
        "4a",
        "the single-pass algorithm speeds every CPU renderer up",
        "least of T(original) / T(single-pass) over sequential, simd_tbb, simd_only, tbb_only",
        tuple(_r(r, st) for r in CPU_RENDERERS for st in ("original", "single-pass")),
        lambda m, p: _min(_gains(m, CPU_RENDERERS)),
        1.0,
        math.inf,
        "every renderer faster: least gain > 1",
        (BUILD,),
    ),
    Claim(
        "4b",
        "... and the SIMD renderers the most",
        "least SIMD gain / greatest scalar gain (simd_tbb, simd_only vs sequential, tbb_only)",
        tuple(_r(r, st) for r in CPU_RENDERERS for st in ("original", "single-pass")),
        lambda m, p: _min(_gains(m, SIMD_RENDERERS)) / _max(_gains(m, SCALAR_RENDERERS)),
        1.0,
        math.inf,
        "SIMD gains most: ratio > 1",
        (BUILD, LANES, OCCUPANCY),
    ),
    Claim(
        "5a",
        "the two extra early exits speed SIMD alone up (single-pass → optimized)",
        "T(simd_only, single-pass) / T(simd_only, optimized)",
        (_r("simd_only", "single-pass"), _r("simd_only", "optimized")),
        lambda m, p: m["simd_only@single-pass"] / m["simd_only@optimized"],
        1.0,
        math.inf,
        "faster: gain > 1",
        (BUILD, LANES, OCCUPANCY),
    ),
    _speedup(
        "5b",
        "... so that SIMD alone beats sequential (optimized)",
        "simd_only",
        "optimized",
        (1.0, math.inf),
        "faster than sequential: S > 1",
        (BUILD, LANES, OCCUPANCY),
    ),
    # One claim, at each stage the thesis' table has.
    *(
        _speedup(
            key,
            f"the GPU is about three orders of magnitude faster than sequential ({stage})",
            "gpu",
            stage,
            (10 ** (ORDERS - 0.5), 10 ** (ORDERS + 0.5)),
            "about 10^3: log10 S in [2.5, 3.5]",
            (BUILD, CORES),
            ("speedup", "gpu"),
        )
        for key, stage in (("6a", "original"), ("6b", "optimized"))
    ),
    _karp_flatt(
        "7a",
        "SIMD + TBB keeps a large serial fraction (optimized; e 0.206)",
        "simd_tbb",
        "threads x lanes",
        (SERIAL_E, math.inf),
        f"same regime, largely serial: e >= {SERIAL_E:g}",
        (BUILD, CORES, LANES, OCCUPANCY),
    ),
    _karp_flatt(
        "7b",
        "the GPU's serial fraction is near zero (optimized; e 0.002)",
        "gpu",
        "the device's estimate",
        (-math.inf, NEAR_ZERO_E),
        f"same regime, near zero: e < {NEAR_ZERO_E:g}",
        (BUILD,),
    ),
]


@dataclass(frozen=True)
class PrecisionClaim:
    """A claim on half precision: the speedup f32/f16 of one renderer's
    headline configuration (the f16 one beside the f32 one) about 2x, and
    the f16 image ruined, i.e. failing the render model's rule against the
    double-precision reference (precision.agrees)."""

    key: str
    text: str
    renderer: str
    stated: float  # the thesis' "twice as fast"; NaN for the kit's own row
    stage: str = "original"  # where the thesis tried it: before single-pass (docs/thesis.md "Stages")
    scene: str = SCENE
    low: float = 2.0 / ABOUT
    high: float = 2.0 * ABOUT
    factors: tuple[str, ...] = (BUILD, LANES)

    @property
    def figure(self) -> str:
        return f"S = T({self.renderer}, f32) / T({self.renderer}, f16), and the f16 image vs the double reference"

    @property
    def line(self) -> str:
        return (
            f"about 2x: S in [2/{ABOUT:g}, 2×{ABOUT:g}], and the f16 image fails render model §8 "
            f"(< {precision.AGREES_WITHIN:.1%} of pixels within 2/255, or < {precision.AGREES_PSNR_DB:g} dB)"
        )


F16_CLAIMS = [
    PrecisionClaim("8", "half precision (8 lanes of f16) doubles the SIMD speed and ruins the image", "simd_only", 2.0),
    PrecisionClaim(
        "8b",
        "not a thesis claim (the kit's extension of 8): half precision doubles the GPU renderer's speed and ruins "
        "its image",
        names.GPU_RENDERER,
        math.nan,
    ),
]

COLUMNS = [
    "claim",
    "text",
    "figure",
    "line",
    "low",
    "high",
    "scene",
    "configurations",
    "thesis",
    "thesis_stated",
    "measured",
    "ci_low",
    "ci_high",
    "verdict",
    "reason",
]


def verdict(ci_low: float, ci_high: float, low: float, high: float) -> str:
    """The verdict of a figure's CI against the claim's region [low, high]."""
    if not (math.isfinite(ci_low) and math.isfinite(ci_high)):
        return NOT_MEASURED
    if low <= ci_low and ci_high <= high:
        return REPRODUCED
    if ci_high < low or ci_low > high:
        return NOT_REPRODUCED
    return INCONCLUSIVE


def optimisation(flags: str, build_type: str) -> str:
    """The -O level of a build: the last -O flag of its compiler flags, else
    what its CMake build type implies (Release -O3, Debug and PaperO0 -O0)."""
    found = re.findall(r"-O[0-9sgz]?", flags or "")
    if found:
        return "-O" if found[-1] == "-O" else found[-1]
    bt = (build_type or "").lower()
    if bt in ("release",):
        return "-O3"
    if bt in ("debug", "papero0"):
        return "-O0"
    return "?"


def evaluate(
    summary: pd.DataFrame,
    frames: pd.DataFrame,
    met: pd.DataFrame,
    thesis_tables: pd.DataFrame,
    thesis_metrics: pd.DataFrame,
    size: tuple[int, int],
    occupancy: pd.DataFrame | None = None,
    refused: dict[str, str] | None = None,
    claims: list[Claim] | None = None,
) -> pd.DataFrame:
    """One row per claim (COLUMNS), in CLAIMS' order, then the F16_CLAIMS.
    `refused`: renderer -> why the bench's probe refused its f16 runs
    (precision.refused)."""
    claims = CLAIMS if claims is None else claims
    heads, halves = (_at_size(tables.headline_rows(summary, p), size) for p in (names.F32, names.F16))
    samples = stats.samples_by_config(frames)
    published = pd.DataFrame(thesis_tables).drop_duplicates(["stage", "renderer", "scene"])
    rows = [_evaluate_one(c, heads, samples, met, frames, published, thesis_metrics, occupancy) for c in claims]
    rows += [_evaluate_precision(c, heads, halves, samples, frames, refused or {}) for c in F16_CLAIMS]
    return pd.DataFrame(rows, columns=COLUMNS)


def _at_size(rows: pd.DataFrame, size: tuple[int, int]) -> pd.DataFrame:
    return rows[(rows[names.WIDTH] == size[0]) & (rows[names.HEIGHT] == size[1])]


def _pick(heads: pd.DataFrame, scene: str, ref: Ref, build: str | None) -> pd.Series | None:
    hit = heads[
        (heads[names.SCENE] == scene) & (heads[names.RENDERER] == ref.renderer) & (heads[names.STAGE] == ref.stage)
    ]
    if build is not None:
        hit = hit[hit[names.BUILD_TYPE] == build]
    return None if hit.empty else hit.iloc[0]


def _p_of(met: pd.DataFrame, row: pd.Series) -> float:
    """p of a configuration as the metrics table has it (threads x lanes, or
    the GPU's estimate); NaN where the metrics table has no row for it."""
    if met.empty:
        return math.nan
    key = stats.config_key(row)
    for _, r in met.iterrows():
        if stats.config_key(r) == key:
            return float(r["p"])
    return math.nan


def _configurations(rows: list[pd.Series]) -> str:
    """'sequential (original, single-pass); simd_tbb 16 threads, 16 lanes AVX3 (original, single-pass)':
    each configuration but for its stage, with the stages it ran at."""
    stages: dict[str, list[str]] = {}
    for row in rows:
        what = " ".join([row[names.RENDERER], tables.describe_config(row)]).strip()
        stages.setdefault(what, []).append(row[names.STAGE])
    return "; ".join(f"{what} ({', '.join(st)})" for what, st in stages.items())


def _claim_fields(claim: Claim | PrecisionClaim) -> dict:
    """The columns every row of a claim starts with: what it says and where it holds."""
    return {
        "claim": claim.key,
        "text": claim.text,
        "figure": claim.figure,
        "line": claim.line,
        "low": claim.low,
        "high": claim.high,
        "scene": claim.scene,
    }


def _evaluate_one(claim, heads, samples, met, frames, published, thesis_metrics, occupancy) -> dict:
    base = {
        **_claim_fields(claim),
        "thesis": _thesis_figure(claim, published),
        "thesis_stated": _stated(claim, thesis_metrics),
    }
    # The first configuration fixes the build the others must share (a speedup compares one build's times).
    first = _pick(heads, claim.scene, claim.refs[0], None)
    build = None if first is None else first[names.BUILD_TYPE]
    rows = {ref.key: _pick(heads, claim.scene, ref, build) for ref in claim.refs}
    missing = [ref for ref, row in zip(claim.refs, rows.values()) if row is None]
    configs = _configurations([r for r in rows.values() if r is not None])
    if missing:
        which = ", ".join(f"{claim.scene}/{ref.renderer}/{ref.stage}" for ref in missing)
        return {
            **base,
            "configurations": configs,
            "measured": math.nan,
            "ci_low": math.nan,
            "ci_high": math.nan,
            "verdict": NOT_MEASURED,
            "reason": f"not in this run: {which}",
        }
    p = {k: _p_of(met, r) for k, r in rows.items()}
    data = {k: samples.get(stats.config_key(r), np.array([])) for k, r in rows.items()}
    value, low, high = figure_ci(claim.compute, data, p)
    result = verdict(low, high, claim.low, claim.high)
    reason = ""
    if result == NOT_MEASURED:
        empty = [k for k, d in data.items() if d.size == 0]
        reason = f"no measured frames of {', '.join(empty)}" if empty else "p unknown (Karp-Flatt: pass --gpu-p)"
    elif result in (NOT_REPRODUCED, INCONCLUSIVE):
        reason = _reason(claim, list(rows.values()), frames, occupancy)
    return {
        **base,
        "configurations": configs,
        "measured": value,
        "ci_low": low,
        "ci_high": high,
        "verdict": result,
        "reason": reason,
    }


def figure_ci(
    compute: Figure, data: dict[str, np.ndarray], p: dict[str, float], seed: int = stats.BOOTSTRAP_SEED
) -> tuple[float, float, float]:
    """(the figure from the medians, its 95 % percentile-bootstrap CI): each
    configuration's frames resampled on their own, the figure evaluated on
    each resample's medians."""
    if any(d.size == 0 for d in data.values()):
        return math.nan, math.nan, math.nan
    with np.errstate(divide="ignore", invalid="ignore"):
        value = float(compute({k: float(np.median(d)) for k, d in data.items()}, p))
        rng = np.random.default_rng(seed)
        resampled = {k: stats.resampled_medians(d, rng) for k, d in data.items()}
        values = np.asarray(compute(resampled, p), dtype=float)
    values = values[np.isfinite(values)]
    if not math.isfinite(value) or values.size == 0:
        return value, math.nan, math.nan
    low, high = stats.percentile_interval(values)
    return value, low, high


def _thesis_figure(claim: Claim, published: pd.DataFrame) -> float:
    """The claim's figure from the thesis' own published times (its p)."""
    times = {}
    for ref in claim.refs:
        hit = published[
            (published["scene"] == claim.scene)
            & (published["renderer"] == ref.renderer)
            & (published["stage"] == ref.stage)
        ]
        if hit.empty:
            return math.nan
        times[ref.key] = float(hit["ms"].iloc[0])
    if not times:
        return math.nan
    p = {ref.key: float(THESIS_P.get(ref.renderer, 1)) for ref in claim.refs}
    return float(claim.compute(times, p))


def _stated(claim: Claim, thesis_metrics: pd.DataFrame) -> float:
    """The value the thesis' text states for the claim's figure, where it states one."""
    if claim.stated is None or thesis_metrics is None or thesis_metrics.empty:
        return math.nan
    metric, renderer = claim.stated
    stage = next(ref.stage for ref in claim.refs if ref.renderer == renderer)
    hit = thesis_metrics[
        (thesis_metrics["stage"] == stage)
        & (thesis_metrics["scene"] == claim.scene)
        & (thesis_metrics["renderer"] == renderer)
    ]
    return float(hit[f"{metric}_reported"].iloc[0]) if len(hit) else math.nan


def _reason(claim: Claim, rows: list[pd.Series], frames: pd.DataFrame, occupancy: pd.DataFrame | None) -> str:
    """What the run's metadata and counters show that differs from the
    thesis' setup, among the claim's factors (docs/thesis.md "Measurement")."""
    parts = []
    if BUILD in claim.factors:
        builds = frames[frames[names.BUILD_TYPE].isin({r[names.BUILD_TYPE] for r in rows})]
        flags = names.META_BUILD_COMPILER_FLAGS
        levels = sorted(
            {
                optimisation(f, b)
                for f, b in zip(builds.get(flags, pd.Series([""] * len(builds))), builds[names.BUILD_TYPE])
            }
        )
        if levels and levels != [THESIS_OPT]:
            parts.append(f"built {', '.join(levels)} (thesis {THESIS_OPT})")
    if CORES in claim.factors:
        cores = sorted({int(c) for c in frames[names.LOGICAL_CORES]})
        models = sorted(set(frames[names.CPU_MODEL]))
        threads = sorted({int(r[names.THREADS]) for r in rows if names.accepts(r[names.RENDERER], names.THREADS)} - {1})
        text = f"{', '.join(map(str, cores))} logical cores ({', '.join(models)})"
        if threads:
            text += f", {', '.join(map(str, threads))} threads"
        parts.append(f"{text} vs the thesis' {THESIS_CORES}")
    if LANES in claim.factors:
        widths = sorted(
            {
                f"{int(r[names.LANES])} lanes {r[names.SIMD_TARGET]}".strip()
                for r in rows
                if r[names.RENDERER] in SIMD_RENDERERS and int(r[names.LANES]) != THESIS_LANES
            }
        )
        if widths:
            parts.append(f"vector width {', '.join(widths)} (thesis {THESIS_LANES} lanes NEON)")
    if OCCUPANCY in claim.factors and occupancy is not None and not occupancy.empty:
        keys = {stats.config_key(r) for r in rows if r[names.RENDERER] in SIMD_RENDERERS}
        for _, o in occupancy.iterrows():
            if stats.config_key(o) in keys and math.isfinite(o[metrics.MASKED_SHARE]):
                parts.append(
                    f"{o[names.RENDERER]} {o[names.STAGE]} masks off {tables.fmt_percent(o[metrics.MASKED_SHARE])} "
                    "of its lane work"
                )
    return "; ".join(parts)


def both_hold(*verdicts: str) -> str:
    """The verdict of a claim made of parts that must all hold: not
    reproduced where one part is not, not measured where one was not
    measured, inconclusive where one is, else reproduced."""
    for outcome in (NOT_REPRODUCED, NOT_MEASURED, INCONCLUSIVE):
        if outcome in verdicts:
            return outcome
    return REPRODUCED


def _evaluate_precision(claim: PrecisionClaim, heads, halves, samples, frames, refused: dict[str, str]) -> dict:
    """A half-precision claim's row: the speedup f32/f16 of the renderer's
    headline configurations with its CI (figure_ci), and the f16 image's agreement."""
    ref = Ref(claim.renderer, claim.stage)
    half = _pick(halves, claim.scene, ref, None)
    twin = None if half is None else _pick(heads, claim.scene, ref, half[names.BUILD_TYPE])
    row = {
        **_claim_fields(claim),
        "thesis": math.nan,
        "thesis_stated": claim.stated,
        "configurations": "",
        "measured": math.nan,
        "ci_low": math.nan,
        "ci_high": math.nan,
        "verdict": NOT_MEASURED,
    }
    where = f"{claim.scene}/{claim.renderer}/{claim.stage}"
    if half is None:
        if claim.renderer in refused:
            return {**row, "reason": f"f16 refused: {refused[claim.renderer]}"}
        return {**row, "reason": f"no f16 run of {where} (profile key precisions = [f32, f16] runs one)"}
    if twin is None:
        return {**row, "configurations": _configurations([half]), "reason": f"no f32 run of {where} beside the f16 one"}
    data = {
        names.F32: samples.get(stats.config_key(twin), np.array([])),
        names.F16: samples.get(stats.config_key(half), np.array([])),
    }
    value, low, high = figure_ci(lambda m, p: m[names.F32] / m[names.F16], data, {})
    agreement = precision.agreement_by_config(frames).get(stats.config_key(half), {})
    ruined = {0.0: REPRODUCED, 1.0: NOT_REPRODUCED}.get(agreement.get("agrees"), NOT_MEASURED)
    result = both_hold(verdict(low, high, claim.low, claim.high), ruined)
    image = f"f16 image against the double reference: {_image_text(agreement)}"
    reason = _reason(claim, [twin, half], frames, None) if result != REPRODUCED else ""
    return {
        **row,
        "configurations": f"f32: {_configurations([twin])}; f16: {_configurations([half])}",
        "measured": value,
        "ci_low": low,
        "ci_high": high,
        "verdict": result,
        "reason": "; ".join(part for part in (image, reason) if part),
    }


def _image_text(agreement: dict) -> str:
    """How far the f16 image is from the double reference, and whether it agrees (precision.agreement_text)."""
    if not agreement or math.isnan(agreement.get("agrees", math.nan)):
        return "not compared (its runs had no --agreement)"
    return precision.agreement_text({precision.side_column(names.F16, k): v for k, v in agreement.items()}, names.F16)


# --- the table ---------------------------------------------------------------------

TITLE = "The thesis' findings, checked"


def findings_table(findings: pd.DataFrame) -> tables.Table:
    rows = []
    for r in findings.itertuples(index=False):
        thesis = fmt_figure(r.thesis)
        if math.isfinite(r.thesis_stated) and not math.isclose(r.thesis_stated, r.thesis, rel_tol=0.02):
            thesis = (
                f"{thesis} (stated {fmt_figure(r.thesis_stated)})"
                if math.isfinite(r.thesis)
                else f"{fmt_figure(r.thesis_stated)} (stated)"
            )
        ours = fmt_figure(r.measured)
        if math.isfinite(r.ci_low):
            ours += f" [{fmt_figure(r.ci_low)}, {fmt_figure(r.ci_high)}]"
        rows.append(
            [
                r.claim,
                r.text,
                f"{r.figure}; {r.scene}" if r.configurations else r.figure,
                r.line,
                r.configurations or tables.MISSING,
                thesis,
                ours,
                f"**{r.verdict}**",
                r.reason,
            ]
        )
    return tables.Table(
        "thesis-findings",
        TITLE,
        ["#", "claim", "figure", "holds when", "configurations (ours)", "thesis", "ours [95% CI]", "verdict", "why"],
        rows,
        "lllllrrll",
        [
            "Verdict: reproduced where the figure's 95% bootstrap CI (each configuration's frames resampled, "
            "2000 times, seeded) lies inside the claim's region, not reproduced where it lies wholly outside, "
            "inconclusive where it straddles a border; not measured where a configuration it needs did not run. "
            "Thesis: the figure from its published times (its p); 'stated' where its text says otherwise. "
            "Configurations: the headline rows (brute force, most threads x lanes, the GPU's default variant). "
            "Why: what differs from the thesis' setup (-O0, Apple M1's 8 cores, 4 NEON lanes), and the lane "
            "counters where the run has them. The lines: docs/thesis.md, 'The findings, checked'."
        ],
    )


def fmt_figure(x: float) -> str:
    """A figure as the findings table shows it: 3 significant digits, whole numbers from 100."""
    if x is None or not math.isfinite(x):
        return tables.MISSING
    if abs(x) >= 100:
        return f"{x:.0f}"
    return tables.fmt_sig(x)
