"""Speedup and the Karp-Flatt metric, as pure functions, and the table of
them for a run's summary; the cost-vs-spheres fits; what the lane counters
(--counters: the SIMD kernel's, and the GPU renderer's per subgroup) give:
rays per second and lane occupancy; and the GPU renderer's variants against
the default one.

Speedup S = T_ref / T_par against the reference renderer at the same scene,
stage and image size (as the thesis did: each table's sequential column).
Karp-Flatt e = (1/S - 1/p) / (1 - 1/p), the experimentally determined serial
fraction: it stays flat when the loss is serial work and grows with p when it
is parallel overhead. p is threads x lanes for the CPU renderers (from the
metadata) and a documented per-device estimate for the GPU
(data/gpu_processors.toml), overridable.
"""

from __future__ import annotations

import math
import re
import tomllib
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from rtbench import names, scenes, stats

GPU_PROCESSORS_FILE = names.REPO_ROOT / "data" / "gpu_processors.toml"


def speedup(t_reference: float, t_parallel: float) -> float:
    """S = T_ref / T_par; NaN where either time is missing or not positive."""
    if not (t_reference > 0 and t_parallel > 0):
        return math.nan
    return t_reference / t_parallel


def karp_flatt(s: float, p: float) -> float:
    """e = (1/S - 1/p) / (1 - 1/p); undefined (NaN) for p <= 1 or no speedup."""
    if not (p > 1 and s > 0) or math.isnan(s) or math.isnan(p):
        return math.nan
    return (1.0 / s - 1.0 / p) / (1.0 - 1.0 / p)


@dataclass(frozen=True)
class GpuEstimate:
    match: str
    p: int | None
    lanes_per_core: int | None
    note: str


def load_gpu_estimates(path: Path = GPU_PROCESSORS_FILE) -> list[GpuEstimate]:
    """The per-device table of GPU processor counts, in file order."""
    with path.open("rb") as f:
        entries = tomllib.load(f).get("device", [])
    return [GpuEstimate(e["match"], e.get("p"), e.get("lanes_per_core"), e.get("note", "")) for e in entries]


def gpu_processors(
    device: str, logical_cores: int, estimates: list[GpuEstimate], override: float | None = None
) -> tuple[float, str]:
    """(p, where it came from) for a GPU device; NaN when nothing matches."""
    if override is not None:
        return float(override), "--gpu-p"
    for e in estimates:
        if re.search(re.escape(e.match), device, re.IGNORECASE):
            if e.p is not None:
                return float(e.p), e.note
            if e.lanes_per_core is not None and logical_cores > 0:
                return float(e.lanes_per_core * logical_cores), e.note
    return math.nan, f"no estimate for device {device or '(unknown)'}; pass --gpu-p"


def processors(
    renderer: str,
    threads: int,
    lanes: int,
    device: str,
    logical_cores: int,
    estimates: list[GpuEstimate],
    gpu_override: float | None = None,
) -> tuple[float, str]:
    """p of one configuration: threads x lanes for a CPU renderer (the schema's
    backend), the device's estimate for one that renders on a GPU."""
    if not names.renders_on_cpu(renderer):
        return gpu_processors(device, logical_cores, estimates, gpu_override)
    return float(threads * max(lanes, 1)), "threads x lanes"


# What a speedup compares at: the same work (scene, stage, accel, image size)
# and build.
SPEEDUP_KEYS = [names.SCENE, names.STAGE, names.ACCEL, names.WIDTH, names.HEIGHT, names.BUILD_TYPE]


def reference_rows(summary: pd.DataFrame, reference: str) -> pd.DataFrame:
    """The reference renderer's rows, one per SPEEDUP_KEYS: the fewest threads
    (ties: the first in summary order)."""
    keys = SPEEDUP_KEYS
    ref = summary[summary[names.RENDERER] == reference]
    return ref.sort_values(names.THREADS, kind="stable").drop_duplicates(keys)[[*keys, "median", "ci_low", "ci_high"]]


def metrics_table(
    summary: pd.DataFrame,
    logical_cores: int,
    estimates: list[GpuEstimate],
    gpu_override: float | None = None,
    reference: str | None = None,
) -> pd.DataFrame:
    """Speedup, p and Karp-Flatt for every non-reference configuration that has
    a reference run at the same scene, stage, accel, size and build. The
    speedup's range divides the reference's bootstrap CI by the
    configuration's (a conservative interval, not a CI of its own)."""
    reference = reference or names.reference_renderer()
    keys = SPEEDUP_KEYS
    ref = reference_rows(summary, reference).rename(
        columns={"median": "ref_median", "ci_low": "ref_ci_low", "ci_high": "ref_ci_high"}
    )
    rows = summary[summary[names.RENDERER] != reference].merge(ref, on=keys, how="inner")
    if rows.empty:
        return pd.DataFrame(
            columns=[
                *summary.columns,
                "ref_median",
                "speedup",
                "speedup_low",
                "speedup_high",
                "p",
                "p_source",
                "karp_flatt",
            ]
        )
    # Grouped by the work they are compared at (each group shares its
    # reference median), groups in order of first appearance, rows within a
    # group in summary order. pandas before 2.2 returned an inner merge in
    # this order, pandas 2.2 in the left frame's order: sorted here, the
    # metrics table and its CSV are the same under both.
    rows = (
        rows.assign(_group=rows.groupby(keys, sort=False, dropna=False).ngroup(), _row=range(len(rows)))
        .sort_values(["_group", "_row"], kind="stable")
        .drop(columns=["_group", "_row"])
        .reset_index(drop=True)
    )
    out = rows.copy()
    out["speedup"] = [speedup(r, t) for r, t in zip(out["ref_median"], out["median"])]
    out["speedup_low"] = [speedup(r, t) for r, t in zip(out["ref_ci_low"], out["ci_high"])]
    out["speedup_high"] = [speedup(r, t) for r, t in zip(out["ref_ci_high"], out["ci_low"])]
    p = [
        processors(r, int(t), int(lanes), d, logical_cores, estimates, gpu_override)
        for r, t, lanes, d in zip(out[names.RENDERER], out[names.THREADS], out[names.LANES], out[names.DEVICE])
    ]
    out["p"] = [v for v, _ in p]
    out["p_source"] = [s for _, s in p]
    out["karp_flatt"] = [karp_flatt(s, pv) for s, pv in zip(out["speedup"], out["p"])]
    return out.drop(columns=["ref_ci_low", "ref_ci_high"])


def scaling_table(summary: pd.DataFrame) -> pd.DataFrame:
    """Strong scaling: for each renderer / lanes / scene / stage / accel /
    traversal / size with more than one thread count, S(t) = T(fewest threads) / T(t) x fewest."""
    keys = [
        names.SCENE,
        names.STAGE,
        names.ACCEL,
        names.TRAVERSAL,
        names.HYBRID_THRESHOLD,
        *names.GPU_AXES,
        names.RENDERER,
        names.LANES,
        names.SIMD_TARGET,
        names.WIDTH,
        names.HEIGHT,
        names.DEVICE,
        names.BUILD_TYPE,
    ]
    parts = []
    for _, group in summary.groupby(keys, sort=False, dropna=False):
        if group[names.THREADS].nunique() < 2:
            continue
        group = group.sort_values(names.THREADS, kind="stable")
        base = group.iloc[0]
        scaled = group.copy()
        scaled["scaling_speedup"] = [speedup(base["median"], t) * base[names.THREADS] for t in group["median"]]
        scaled["efficiency"] = scaled["scaling_speedup"] / scaled[names.THREADS]
        parts.append(scaled)
    if not parts:
        return pd.DataFrame(columns=[*summary.columns, "scaling_speedup", "efficiency"])
    return pd.concat(parts, ignore_index=True)


# --- start-up vs spheres -------------------------------------------------------------

STARTUP_KEYS = [names.SCENE, names.SPHERES, names.ACCEL]


def startup_times(frames: pd.DataFrame) -> pd.DataFrame:
    """Median load, build and prepare time per scene and accel, one value per
    run (every frame of a run carries the same ones); empty where no run
    recorded its load time (runs from before it was)."""
    if names.LOAD_MS not in frames or frames[names.LOAD_MS].isna().all():
        return pd.DataFrame()
    runs = frames.drop_duplicates([names.SOURCE, names.CONFIG_ID, names.REPETITION])
    grouped = runs.groupby(STARTUP_KEYS, sort=True)
    table = grouped[[names.LOAD_MS, names.BUILD_MS, names.PREPARE_MS]].median()
    table["runs"] = grouped.size()
    return table.reset_index().sort_values([names.SPHERES, names.SCENE, names.ACCEL], ignore_index=True)


# --- cost vs spheres ---------------------------------------------------------------

# A configuration but for its scene: the points of one cost-vs-spheres curve.
CURVE_KEYS = [k for k in names.CONFIG_KEYS if k not in (names.SCENE, names.SPHERES)]
# A curve needs this many distinct sphere counts before its exponent is fitted.
MIN_SPHERE_COUNTS = 3
CURVE = "curve"


def power_law_fit(spheres, ms) -> tuple[float, float, float]:
    """The least-squares line through (log N, log ms), i.e. ms = c N^k:
    (k, c, r^2 of the line in log-log space). NaNs for fewer than two
    distinct N.

    In closed form over math.log and math.fsum, not np.log and np.polyfit:
    NumPy 2's vectorised log and the LAPACK under polyfit round the last bits
    otherwise than NumPy 1.24's, and report/data/cost_vs_spheres.csv holds
    these numbers at full precision, the same on every release."""
    x = [math.log(float(n)) for n in spheres]
    y = [math.log(float(v)) for v in ms]
    if len(x) < 2 or min(x) == max(x):
        return math.nan, math.nan, math.nan
    mean_x, mean_y = math.fsum(x) / len(x), math.fsum(y) / len(y)
    dx = [v - mean_x for v in x]
    dy = [v - mean_y for v in y]
    k = math.fsum(a * b for a, b in zip(dx, dy)) / math.fsum(a * a for a in dx)
    log_c = mean_y - k * mean_x
    residual = math.fsum((b - (k * a + log_c)) ** 2 for a, b in zip(x, y))
    spread = math.fsum(b * b for b in dy)
    r2 = 1.0 - residual / spread if spread > 0 else 1.0
    return k, math.exp(log_c), r2


def sphere_curves(summary: pd.DataFrame, min_counts: int = MIN_SPHERE_COUNTS) -> pd.DataFrame:
    """The summary rows that lie on a cost-vs-spheres curve: configurations
    equal but for the scene, with a positive median on at least `min_counts`
    distinct sphere counts. Column `curve` numbers the curves 0, 1, ...; rows
    sorted by curve, then sphere count. The corpus' scenes (groundN,
    clustersN, ...: rtbench/scenes.py) differ from the uniform ones in
    layout, not only in count, so no curve runs through them."""
    corpus = summary[names.SCENE].map(lambda scene: scenes.family_of(str(scene)) in scenes.CORPUS_FAMILIES)
    usable = summary[(summary[names.SPHERES] > 0) & (summary["median"] > 0) & ~corpus.astype(bool)]
    parts = []
    for _, group in usable.groupby(CURVE_KEYS, sort=False, dropna=False):
        if group[names.SPHERES].nunique() >= min_counts:
            parts.append(group.sort_values([names.SPHERES, names.SCENE]).assign(**{CURVE: len(parts)}))
    if not parts:
        return pd.DataFrame(columns=[*summary.columns, CURVE])
    return pd.concat(parts, ignore_index=True)


def cost_fits(curves: pd.DataFrame) -> pd.DataFrame:
    """One row per curve of sphere_curves: its CURVE_KEYS, the sphere counts
    and medians at both ends, and the fitted exponent k of median render_ms
    = c N^k (1: the cost grows with the sphere count; 0: not at all)."""
    rows = []
    for curve, group in curves.groupby(CURVE, sort=True):
        k, c, r2 = power_law_fit(group[names.SPHERES], group["median"])
        first, last = group.iloc[0], group.iloc[-1]
        rows.append(
            {
                CURVE: curve,
                **{key: first[key] for key in CURVE_KEYS},
                "counts": int(group[names.SPHERES].nunique()),
                "spheres_min": int(first[names.SPHERES]),
                "spheres_max": int(last[names.SPHERES]),
                "ms_min": first["median"],
                "ms_max": last["median"],
                "exponent": k,
                "coefficient": c,
                "r2": r2,
            }
        )
    columns = [
        CURVE,
        *CURVE_KEYS,
        "counts",
        "spheres_min",
        "spheres_max",
        "ms_min",
        "ms_max",
        "exponent",
        "coefficient",
        "r2",
    ]
    return pd.DataFrame(rows, columns=columns)


# --- lane counters (--counters) ------------------------------------------------------

MRAYS_PER_S = "mrays_per_s"
# Which time column Mrays/s divided by (rate_time).
MRAYS_TIME = "mrays_time"
FRAMES = "frames"
MASKED_SHARE = "masked_share"
# Per kind of lane work (names.LANE_WORK): its occupancy column, active / slots.
OCCUPANCY = {kind: f"{kind}_occupancy" for kind in names.LANE_WORK}
RAYS_PER_FRAME = "rays_per_frame"
NODE_VISITS_PER_FRAME = "node_visits_per_frame"
SPHERE_TESTS_PER_FRAME = "sphere_tests_per_frame"


def counted(frames: pd.DataFrame) -> pd.DataFrame:
    """The measured frames that carry counters (runs with --counters)."""
    measured = stats.measured(frames)
    return measured[measured[names.RAYS].notna()]


def has_counters(frames: pd.DataFrame) -> bool:
    return not counted(frames).empty


def rate_time(group: pd.DataFrame) -> str:
    """The time column Mrays/s divides by for one configuration's frames:
    gpu_ms (the device time of the render dispatches) for a renderer on a
    Vulkan device that measured it in every frame, render_ms otherwise. The
    GPU renderer's render_ms is host time around a submit and a wait, which
    for a frame of a millisecond or two is mostly not the tracing."""
    renderer = group[names.RENDERER].iloc[0]
    gpu = group[names.GPU_MS].astype(float)
    if not names.renders_on_cpu(renderer) and gpu.notna().all():
        return names.GPU_MS
    return names.RENDER_MS


def throughput(frames: pd.DataFrame) -> pd.DataFrame:
    """Per configuration with counters: Mrays/s, the median over its measured
    frames of rays (all bounce depths) / time / 1000, i.e. millions of rays
    per second of the Render phase (render_ms), or of the GPU's dispatches
    (gpu_ms, rate_time); MRAYS_TIME names the column."""
    rows = []
    for key, group in counted(frames).groupby(names.CONFIG_KEYS, sort=False, dropna=False):
        time = rate_time(group)
        rays = group[names.RAYS].astype(float).to_numpy()
        ms = group[time].astype(float).to_numpy()
        per_frame = [r / t / 1000.0 for r, t in zip(rays, ms) if t > 0]
        rows.append({**dict(zip(names.CONFIG_KEYS, key)), MRAYS_PER_S: stats.median(per_frame), MRAYS_TIME: time})
    return pd.DataFrame(rows, columns=[*names.CONFIG_KEYS, MRAYS_PER_S, MRAYS_TIME])


def with_throughput(summary: pd.DataFrame, frames: pd.DataFrame) -> pd.DataFrame:
    """The summary with its Mrays/s column where the runs have counters
    (NaN for configurations without); the summary as it is otherwise."""
    if not has_counters(frames):
        return summary
    return summary.merge(throughput(frames), on=names.CONFIG_KEYS, how="left")


def lane_occupancy(frames: pd.DataFrame) -> pd.DataFrame:
    """Per configuration with counters, from its counters summed over the
    measured frames: rays, node visits and sphere tests per frame, each kind
    of lane work's occupancy (lanes active / lane slots; NaN where it had no
    slots), and the masked share of all lane work, 1 - sum(active) / sum(slots)
    over node visits, sphere tests and shading: the vector lanes whose work
    was thrown away. Sorted as the summary."""
    rows = []
    for key, group in counted(frames).groupby(names.CONFIG_KEYS, sort=False, dropna=False):
        sums = {c: int(group[c].sum()) for c in names.COUNTER_COLUMNS if c != names.RAYS_PER_DEPTH}
        n = len(group)
        row = {**dict(zip(names.CONFIG_KEYS, key)), FRAMES: n, **sums}
        row[RAYS_PER_FRAME] = sums[names.RAYS] / n
        row[NODE_VISITS_PER_FRAME] = sums[names.NODE_VISITS] / n
        row[SPHERE_TESTS_PER_FRAME] = sums[names.SPHERE_TESTS] / n
        for kind, (slots, active) in names.LANE_WORK.items():
            row[OCCUPANCY[kind]] = _share(sums[active], sums[slots])
        all_slots = sum(sums[slots] for slots, _ in names.LANE_WORK.values())
        all_active = sum(sums[active] for _, active in names.LANE_WORK.values())
        row[MASKED_SHARE] = 1.0 - _share(all_active, all_slots)
        rows.append(row)
    columns = [
        *names.CONFIG_KEYS,
        FRAMES,
        *(c for c in names.COUNTER_COLUMNS if c != names.RAYS_PER_DEPTH),
        RAYS_PER_FRAME,
        NODE_VISITS_PER_FRAME,
        SPHERE_TESTS_PER_FRAME,
        *OCCUPANCY.values(),
        MASKED_SHARE,
    ]
    table = pd.DataFrame(rows, columns=columns)
    return stats.sort_configs(table) if rows else table


def _share(part: float, whole: float) -> float:
    return part / whole if whole > 0 else math.nan


# --- the GPU renderers' variants (gpu_bvh; gpu_rt_reorder) -------------------------------

GPU_MS_MEDIAN = "gpu_ms_median"
GPU_MS_CI_LOW = "gpu_ms_ci_low"
GPU_MS_CI_HIGH = "gpu_ms_ci_high"
# The default variant's median gpu_ms over this one's: > 1, this variant is faster.
SPEEDUP_OVER_DEFAULT = "speedup_over_default"
# gpu_rt only: the compute gpu renderer's median gpu_ms in its default variant
# on its BVH (binary) over this one's, at the same scene,
# stage, size, device and build: > 1, the ray-tracing pipeline is faster.
SPEEDUP_OVER_GPU = "speedup_over_gpu"
# What makes a gpu_rt configuration and the gpu's comparable (SPEEDUP_OVER_GPU).
SAME_WORK_KEYS = [names.SCENE, names.STAGE, names.WIDTH, names.HEIGHT, names.DEVICE, names.BUILD_TYPE]


def has_gpu_variants(frames: pd.DataFrame) -> bool:
    """Whether a GPU configuration of the run ran a variant other than the
    default (names.gpu_tag), of the gpu renderer or of gpu_rt."""
    gpu = frames[frames[names.RENDERER].isin(names.GPU_MS_RENDERERS)]
    return any(names.gpu_tag(*values) for values in zip(*(gpu[axis] for axis in names.GPU_AXES)))


def has_gpu_rt(frames: pd.DataFrame) -> bool:
    """Whether the gpu_rt renderer measured gpu_ms in the run."""
    rt = frames[frames[names.RENDERER] == names.GPU_RT_RENDERER]
    return bool(rt[names.GPU_MS].notna().any())


def has_gpu_ms_table(frames: pd.DataFrame) -> bool:
    """Whether the run has device times to set side by side: variants of a
    GPU renderer besides the default, or the gpu_rt renderer (beside the
    compute renderer it is the point of the comparison)."""
    return has_gpu_variants(frames) or has_gpu_rt(frames)


def gpu_variants(frames: pd.DataFrame) -> pd.DataFrame:
    """Per configuration of a renderer that times its frames on the device
    (names.GPU_MS_RENDERERS: gpu and gpu_rt) and measured gpu_ms in its
    measured frames: their count, the median gpu_ms (the device time of the
    frame's dispatch or ray trace) with its bootstrap CI, and its speedup
    over the default variant of the same configuration otherwise (gpu:
    binary BVH; gpu_rt: no reorder); NaN where that did not run. gpu_rt rows
    also get their speedup over the gpu renderer's default variant on its BVH
    (SPEEDUP_OVER_GPU; NaN on the gpu's rows). Empty unless the run has a
    variant besides the default or gpu_rt (has_gpu_ms_table). Sorted as the
    summary: gpu_rt beside gpu in each scene."""
    columns = [
        *names.CONFIG_KEYS,
        "n",
        GPU_MS_MEDIAN,
        GPU_MS_CI_LOW,
        GPU_MS_CI_HIGH,
        SPEEDUP_OVER_DEFAULT,
        SPEEDUP_OVER_GPU,
    ]
    if not has_gpu_ms_table(frames):
        return pd.DataFrame(columns=columns)
    measured = stats.measured(frames)
    gpu = measured[measured[names.RENDERER].isin(names.GPU_MS_RENDERERS) & measured[names.GPU_MS].notna()]
    rows = []
    for key, group in gpu.groupby(names.CONFIG_KEYS, sort=False, dropna=False):
        summary = stats.summarize(group[names.GPU_MS].to_numpy())
        rows.append(
            {
                **dict(zip(names.CONFIG_KEYS, key)),
                "n": summary["n"],
                GPU_MS_MEDIAN: summary["median"],
                GPU_MS_CI_LOW: summary["ci_low"],
                GPU_MS_CI_HIGH: summary["ci_high"],
            }
        )
    table = pd.DataFrame(rows, columns=columns)
    # Each row's median by (the other configuration keys, its GPU variant); str() makes NA keys comparable.
    others = [k for k in names.CONFIG_KEYS if k not in names.GPU_AXES]
    medians = {
        (tuple(str(r[k]) for k in others), tuple(r[axis] for axis in names.GPU_AXES)): r[GPU_MS_MEDIAN]
        for _, r in table.iterrows()
    }

    def default_median(row) -> float:
        default = tuple(names.GPU_AXIS_VALUES[axis][1] if row[axis] else "" for axis in names.GPU_AXES)
        return medians.get((tuple(str(row[k]) for k in others), default), math.nan)

    table[SPEEDUP_OVER_DEFAULT] = [speedup(default_median(r), r[GPU_MS_MEDIAN]) for _, r in table.iterrows()]
    table[SPEEDUP_OVER_GPU] = _speedup_over_gpu(table)
    return stats.sort_configs(table) if rows else table


def _speedup_over_gpu(table: pd.DataFrame) -> list[float]:
    """SPEEDUP_OVER_GPU of each row of gpu_variants' table."""
    compute_default = tuple(names.GPU_AXIS_VALUES[axis][1] for axis in names.gpu_axes_of(names.GPU_RENDERER, names.BVH))
    baseline = {
        tuple(str(r[k]) for k in SAME_WORK_KEYS): r[GPU_MS_MEDIAN]
        for _, r in table.iterrows()
        if r[names.RENDERER] == names.GPU_RENDERER
        and r[names.ACCEL] == names.BVH
        and tuple(r[axis] for axis in names.gpu_axes_of(names.GPU_RENDERER, names.BVH)) == compute_default
    }
    return [
        speedup(baseline.get(tuple(str(r[k]) for k in SAME_WORK_KEYS), math.nan), r[GPU_MS_MEDIAN])
        if r[names.RENDERER] == names.GPU_RT_RENDERER
        else math.nan
        for _, r in table.iterrows()
    ]
