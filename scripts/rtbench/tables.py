"""The report's tables: built as data (`Table`), rendered to Markdown and LaTeX.

Builders take the summary (one row per configuration, from stats) and the
thesis' data, and return `Table`s; rendering is separate, so the same table
goes to report/README.md, report/tables/*.md and report/tables/*.tex.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import pandas as pd

from rtbench import metrics, names
from rtbench.thesis import TableSpec

MISSING = "–"


@dataclass(frozen=True)
class Table:
    slug: str
    title: str
    headers: list[str]
    rows: list[list[str]]
    align: str  # one of 'l' / 'r' per column
    notes: list[str] = field(default_factory=list)


# --- number formatting ------------------------------------------------------------


def fmt_ms(x: float) -> str:
    """Milliseconds with about four significant digits."""
    if x is None or not math.isfinite(x):
        return MISSING
    if abs(x) >= 100:
        return f"{x:.1f}"
    if abs(x) >= 10:
        return f"{x:.2f}"
    return f"{x:.3f}"


def fmt_fixed(x: float, digits: int = 3) -> str:
    return MISSING if x is None or not math.isfinite(x) else f"{x:.{digits}f}"


def fmt_sig(x: float, digits: int = 3) -> str:
    """Significant digits, for values spanning magnitudes (Karp-Flatt)."""
    if x is None or not math.isfinite(x):
        return MISSING
    return f"{x:.{digits}g}" if abs(x) >= 1e-4 or x == 0 else f"{x:.{digits - 1}e}"


def fmt_percent(x: float) -> str:
    return MISSING if x is None or not math.isfinite(x) else f"{x:.1%}"


def fmt_int(x) -> str:
    return MISSING if x is None or (isinstance(x, float) and not math.isfinite(x)) else str(int(x))


# --- rendering ------------------------------------------------------------------


def to_markdown(table: Table) -> str:
    """A GitHub-flavoured Markdown table with its title and notes."""

    def cells(values: list[str]) -> str:
        return "| " + " | ".join(v.replace("|", "\\|") for v in values) + " |"

    rule = "|" + "|".join(":--" if a == "l" else "--:" for a in table.align) + "|"
    lines = [f"**{table.title}**", "", cells(table.headers), rule, *(cells(r) for r in table.rows)]
    for note in table.notes:
        lines += ["", note]
    return "\n".join(lines) + "\n"


LATEX_SPECIALS = {
    "\\": r"\textbackslash{}",
    "&": r"\&",
    "%": r"\%",
    "$": r"\$",
    "#": r"\#",
    "_": r"\_",
    "{": r"\{",
    "}": r"\}",
    "~": r"\textasciitilde{}",
    "^": r"\textasciicircum{}",
    "–": "--",
    "×": r"$\times$",
    "±": r"$\pm$",
    "→": r"$\rightarrow$",
    "²": r"$^2$",
}


def latex_escape(text: str) -> str:
    return "".join(LATEX_SPECIALS.get(ch, ch) for ch in text)


def to_latex(table: Table) -> str:
    """A booktabs table environment (needs \\usepackage{booktabs})."""

    def cells(values: list[str]) -> str:
        return " & ".join(latex_escape(v) for v in values) + r" \\"

    lines = [
        r"\begin{table}[ht]",
        r"\centering",
        rf"\caption{{{latex_escape(table.title)}}}",
        rf"\label{{tab:{table.slug}}}",
        rf"\begin{{tabular}}{{{table.align}}}",
        r"\toprule",
        cells(table.headers),
        r"\midrule",
        *(cells(r) for r in table.rows),
        r"\bottomrule",
        r"\end{tabular}",
    ]
    lines += [rf"\par\small {latex_escape(n)}" for n in table.notes]
    lines.append(r"\end{table}")
    return "\n".join(lines) + "\n"


# --- choosing configurations ---------------------------------------------------


def sizes(summary: pd.DataFrame) -> list[tuple[int, int]]:
    """Image sizes in the run, the one with the most configurations first
    (ties: the larger image), which the thesis comparisons use."""
    counts = summary.groupby([names.WIDTH, names.HEIGHT]).size().reset_index(name="n")
    counts["area"] = counts[names.WIDTH] * counts[names.HEIGHT]
    counts = counts.sort_values(["n", "area"], ascending=False)
    return [(int(w), int(h)) for w, h in zip(counts[names.WIDTH], counts[names.HEIGHT])]


def headline_rows(summary: pd.DataFrame, precision: str = names.F32) -> pd.DataFrame:
    """One configuration per (scene, renderer, stage, size, build) as the
    thesis ran it: brute force (accel none) in f32, and of those the one with
    the most threads x lanes, i.e. the whole machine, and the GPU renderer's
    default variant (one_gpu_variant). All others stay in the summary table;
    `precision` f16 picks the half-precision experiment's rows instead."""
    chosen = summary[(summary[names.ACCEL] == names.BRUTE_FORCE) & (summary[names.PRECISION] == precision)]
    return one_gpu_variant(widest_rows(chosen))


# What a configuration is but for its threads and lanes (widest_rows) or its GPU variant (one_gpu_variant).
WORK_KEYS = [names.SCENE, names.RENDERER, names.STAGE, names.ACCEL, names.TRAVERSAL, names.HYBRID_THRESHOLD]
SIZE_BUILD_KEYS = [names.WIDTH, names.HEIGHT, names.BUILD_TYPE]


def widest_rows(summary: pd.DataFrame) -> pd.DataFrame:
    """One configuration per (scene, renderer, stage, accel, traversal, GPU
    variant, size, build): the one with the most threads x lanes (ties: the
    most lanes)."""
    df = summary.assign(_p=summary[names.THREADS] * summary[names.LANES].clip(lower=1))
    df = df.sort_values(["_p", names.LANES], ascending=False, kind="stable")
    return df.drop_duplicates([*WORK_KEYS, *names.GPU_AXES, *SIZE_BUILD_KEYS]).drop(columns="_p")


def one_gpu_variant(rows: pd.DataFrame) -> pd.DataFrame:
    """The rows less all but one GPU variant of each configuration: the
    default variant (names.gpu_tag empty: the way the GPU renderer ran before
    its variants) where it ran, else the first in the schema's order. Rows
    keep their order."""
    rank = [
        tuple(names.gpu_order(axis, value) for axis, value in zip(names.GPU_AXES, values))
        for values in zip(*(rows[axis] for axis in names.GPU_AXES))
    ]
    ranked = rows.assign(_rank=rank).sort_values("_rank", kind="stable")
    kept = ranked.drop_duplicates([*WORK_KEYS, *SIZE_BUILD_KEYS]).index
    return rows.loc[rows.index.isin(kept)]


def _at_size(df: pd.DataFrame, size: tuple[int, int]) -> pd.DataFrame:
    return df[(df[names.WIDTH] == size[0]) & (df[names.HEIGHT] == size[1])]


def _lookup(df: pd.DataFrame, **match) -> pd.Series | None:
    mask = pd.Series(True, index=df.index)
    for column, value in match.items():
        mask &= df[column] == value
    hits = df[mask]
    return None if hits.empty else hits.iloc[0]


def describe_config(row: pd.Series) -> str:
    """'8 threads, 4 lanes NEON' for a CPU renderer (what it takes), the device for the others."""
    if not names.renders_on_cpu(row[names.RENDERER]):
        return row[names.DEVICE] or "device unknown"
    parts = [f"{value} {option}" for option, value in names.label_options(row)]
    target = [row[names.SIMD_TARGET]] if names.accepts(row[names.RENDERER], names.LANES) else []
    return " ".join([", ".join(parts), *target]).strip()


# --- builders ----------------------------------------------------------------------


def thesis_mirror(
    summary: pd.DataFrame, spec: TableSpec, size: tuple[int, int], scenes: list[str], name_size: bool = False
) -> Table:
    """Our run in the shape of one thesis table: scenes x renderers, median
    render time per frame. name_size: the run has several sizes, so the
    size is in the table's slug and title (two Table 1s: which is which)."""
    heads = _at_size(headline_rows(summary), size)
    heads = heads[heads[names.STAGE] == spec.stage]
    rows, used = [], {}
    for scene in scenes:
        row = [scene]
        for renderer in spec.renderers:
            hit = _lookup(heads, **{names.SCENE: scene, names.RENDERER: renderer})
            row.append(fmt_ms(hit["median"]) if hit is not None else MISSING)
            if hit is not None and describe_config(hit):
                used.setdefault(renderer, describe_config(hit))
        rows.append(row)
    notes = [
        f"Median render_ms of the measured frames, {size[0]}x{size[1]}, stage {spec.stage}; "
        f"{MISSING} = not in this run."
    ]
    if used:
        notes.append("Configurations: " + "; ".join(f"{r}: {d}" for r, d in used.items()) + ".")
    notes += _brute_force_note(summary)
    size_text = f"{size[0]}x{size[1]}"
    slug, name = f"table{spec.number}-{spec.stage}", f"Table {spec.number} ({spec.stage})"
    if name_size:
        slug, name = f"{slug}-{size_text}", f"{name}, {size_text}"
    return Table(
        slug,
        f"{name}: render time per frame [ms]",
        ["scene", *spec.renderers],
        rows,
        "l" + "r" * len(spec.renderers),
        notes,
    )


def _brute_force_note(summary: pd.DataFrame) -> list[str]:
    """A note for the thesis comparisons of a run that also searched otherwise
    than by brute force (none for a run of brute force only)."""
    others = sorted(set(summary[names.ACCEL]) - {names.BRUTE_FORCE}, key=names.accel_order)
    if not others:
        return []
    return [
        f"Brute force only ({names.ACCEL} {names.BRUTE_FORCE}, the thesis' algorithm); the "
        f"{', '.join(others)} configurations are in the summary table."
    ]


def side_by_side(summary: pd.DataFrame, thesis_tables: pd.DataFrame, size: tuple[int, int]) -> Table:
    """Every published figure next to ours: times (not comparable across
    machines and -O0 vs -O3) and speedups over the reference (comparable)."""
    reference = names.reference_renderer()
    heads = _at_size(headline_rows(summary), size)
    rows = []
    for rec in thesis_tables.itertuples(index=False):
        ours = _lookup(heads, **{names.SCENE: rec.scene, names.RENDERER: rec.renderer, names.STAGE: rec.stage})
        ours_ref = _lookup(heads, **{names.SCENE: rec.scene, names.RENDERER: reference, names.STAGE: rec.stage})
        thesis_ref = thesis_tables[
            (thesis_tables["stage"] == rec.stage)
            & (thesis_tables["scene"] == rec.scene)
            & (thesis_tables["renderer"] == reference)
        ]["ms"]
        ours_ms = ours["median"] if ours is not None else math.nan
        ref_ms = ours_ref["median"] if ours_ref is not None else math.nan
        thesis_s = thesis_ref.iloc[0] / rec.ms if len(thesis_ref) else math.nan
        rows.append(
            [
                str(rec.table),
                rec.stage,
                rec.renderer,
                rec.scene,
                fmt_ms(rec.ms),
                fmt_ms(ours_ms),
                fmt_fixed(thesis_s),
                fmt_fixed(ref_ms / ours_ms if ours_ms > 0 else math.nan),
            ]
        )
    return Table(
        "thesis-vs-ours",
        f"The thesis' published times beside ours ({size[0]}x{size[1]})",
        [
            "table",
            "stage",
            "renderer",
            "scene",
            "thesis ms",
            "ours ms",
            f"thesis S vs {reference}",
            f"ours S vs {reference}",
        ],
        rows,
        "lllrrrrr",
        [
            f"Thesis: mean per frame, 800x600, Apple M1, -O0. Ours: median per frame on this run's machine and build. "
            f"Times differ by machine and compiler settings; the speedups over {reference} are what compares."
        ],
    )


def stage_effects(summary: pd.DataFrame, thesis_tables: pd.DataFrame, size: tuple[int, int]) -> Table:
    """What each step of the thesis' story buys, per renderer and scene: the
    single-pass algorithm over the two-pass original, then the extra early
    exits; as time ratios (> 1 = faster), ours beside the thesis'."""
    stage_names = list(names.STAGES)
    heads = _at_size(headline_rows(summary), size)
    published = thesis_tables.drop_duplicates(["stage", "renderer", "scene"])
    rows = []
    for scene in pd.unique(heads[names.SCENE]):
        for renderer in sorted(pd.unique(heads[names.RENDERER]), key=names.renderer_order):
            ours = [_median_of(heads, scene, renderer, st) for st in stage_names]
            theirs = [_thesis_ms(published, scene, renderer, st) for st in stage_names]
            gains = [_ratio(ours[i], ours[i + 1]) for i in range(len(stage_names) - 1)]
            thesis_gains = [_ratio(theirs[i], theirs[i + 1]) for i in range(len(stage_names) - 1)]
            rows.append(
                [
                    scene,
                    renderer,
                    *map(fmt_ms, ours),
                    *(f"{fmt_fixed(g, 2)} ({fmt_fixed(t, 2)})" for g, t in zip(gains, thesis_gains)),
                ]
            )
    steps = [f"{a} → {b}" for a, b in itertools.pairwise(stage_names)]
    return Table(
        "stage-effects",
        f"What the stages change: median render_ms and speedup of each step ({size[0]}x{size[1]})",
        ["scene", "renderer", *(f"{st} ms" for st in stage_names), *(f"{s} ours (thesis)" for s in steps)],
        rows,
        "ll" + "r" * (2 * len(stage_names) - 1),
        [
            "A step's speedup is the time before it divided by the time after it (> 1: the step helped). "
            "The stages differ by algorithm (two-pass → single-pass) and early exits "
            "(see schema/rt_schema.json); sphere and discriminant exits only change the SIMD renderers."
        ],
    )


def _median_of(heads: pd.DataFrame, scene: str, renderer: str, stage: str) -> float:
    hit = _lookup(heads, **{names.SCENE: scene, names.RENDERER: renderer, names.STAGE: stage})
    return hit["median"] if hit is not None else math.nan


def _thesis_ms(published: pd.DataFrame, scene: str, renderer: str, stage: str) -> float:
    hit = published[(published["scene"] == scene) & (published["renderer"] == renderer) & (published["stage"] == stage)]
    return float(hit["ms"].iloc[0]) if len(hit) else math.nan


def _ratio(before: float, after: float) -> float:
    return before / after if before > 0 and after > 0 else math.nan


# The columns that name a configuration, first in the per-configuration
# tables: (header, alignment, cell of a row as a dict).
CONFIG_COLUMNS = [
    ("stage", "l", lambda d: d[names.STAGE]),
    ("scene", "l", lambda d: d[names.SCENE]),
    ("renderer", "l", lambda d: d[names.RENDERER]),
    (names.ACCEL, "l", lambda d: accel_text(d)),
    ("size", "l", lambda d: f"{d[names.WIDTH]}x{d[names.HEIGHT]}"),
    ("threads", "r", lambda d: fmt_int(d[names.THREADS])),
    ("lanes", "r", lambda d: fmt_int(d[names.LANES])),
    ("target / device", "l", lambda d: _target_or_device(d)),
]


def accel_text(d: dict) -> str:
    """The accel, the traversal where it is not packets and the GPU variants
    where they are not the defaults (names.variant_tag): 'bvh', 'bvh single',
    'bvh hybrid8', 'bvh wide', 'bvh hit-reorder'."""
    return " ".join([d[names.ACCEL], *names.variant_tag(d)])


def _config_columns(leave_out: tuple[str, ...] = ()) -> list[tuple]:
    return [column for column in CONFIG_COLUMNS if column[0] not in leave_out]


def _config_headers(leave_out: tuple[str, ...] = ()) -> tuple[list[str], str]:
    """The configuration columns' headers and alignment, less `leave_out`."""
    columns = _config_columns(leave_out)
    return [header for header, _, _ in columns], "".join(align for _, align, _ in columns)


def _config_cells(d: dict, leave_out: tuple[str, ...] = ()) -> list[str]:
    """A configuration row's cells of the configuration columns, less `leave_out`."""
    return [cell(d) for _, _, cell in _config_columns(leave_out)]


def _config_rows(
    frame: pd.DataFrame, stats: Callable[[dict], list[str]], leave_out: tuple[str, ...] = ()
) -> list[list[str]]:
    """One row per configuration of `frame`: its configuration cells (less
    `leave_out`), then `stats` of it."""
    return [[*_config_cells(d, leave_out), *stats(d)] for d in (r._asdict() for r in frame.itertuples(index=False))]


def config_headers(leave_out: tuple[str, ...] = ()) -> tuple[list[str], str]:
    """The configuration columns' headers and alignment, for tables built elsewhere (budget, compare)."""
    return _config_headers(leave_out)


def config_cells(d: dict, leave_out: tuple[str, ...] = ()) -> list[str]:
    """A configuration row's cells, for tables built elsewhere (budget, compare)."""
    return _config_cells(d, leave_out)


def _target_or_device(d: dict) -> str:
    """A CPU renderer's SIMD target (empty for scalar ones), else the device it rendered on."""
    return d[names.SIMD_TARGET] if names.renders_on_cpu(d[names.RENDERER]) else d[names.DEVICE]


def metrics_our(metrics: pd.DataFrame) -> Table:
    """Speedup and Karp-Flatt of every configuration of our run."""

    def stats(d: dict) -> list[str]:
        return [
            fmt_ms(d["ref_median"]),
            fmt_ms(d["median"]),
            f"{fmt_fixed(d['speedup'])} [{fmt_fixed(d['speedup_low'], 2)}, {fmt_fixed(d['speedup_high'], 2)}]",
            fmt_int(d["p"]) if math.isfinite(d["p"]) else MISSING,
            fmt_sig(d["karp_flatt"]),
        ]

    rows = _config_rows(metrics, stats)
    reference = names.reference_renderer()
    headers, align = _config_headers()
    return Table(
        "metrics",
        f"Speedup over {reference} and Karp-Flatt metric (our run)",
        [*headers, f"{reference} ms", "ms", "S [range]", "p", "e"],
        rows,
        align + "rrlrr",
        [
            "S = T_ref / T (medians); range from the bootstrap CIs; e = (1/S - 1/p)/(1 - 1/p). "
            "p = threads x lanes on the CPU; on the GPU the per-device estimate of data/gpu_processors.toml "
            "(or --gpu-p). e is undefined for p = 1."
        ],
    )


def metrics_vs_thesis(thesis_metrics: pd.DataFrame, metrics: pd.DataFrame, size: tuple[int, int]) -> Table:
    """The thesis' stated metrics, what its table gives, and ours."""
    ours = _at_size(headline_rows(metrics), size)
    rows = []
    for r in thesis_metrics.itertuples(index=False):
        hit = _lookup(ours, **{names.STAGE: r.stage, names.SCENE: r.scene, names.RENDERER: r.renderer})
        s, p, e = (hit["speedup"], hit["p"], hit["karp_flatt"]) if hit is not None else (math.nan,) * 3
        rows.append(
            [
                r.stage,
                r.scene,
                r.renderer,
                fmt_fixed(r.speedup_reported),
                fmt_fixed(r.speedup_recomputed),
                fmt_int(r.p),
                fmt_sig(r.karp_flatt_reported),
                fmt_sig(r.karp_flatt_recomputed),
                fmt_fixed(s),
                fmt_int(p) if math.isfinite(p) else MISSING,
                fmt_sig(e),
            ]
        )
    return Table(
        "metrics-vs-thesis",
        "Speedup and Karp-Flatt: the thesis as stated, as its own table gives, and ours",
        [
            "stage",
            "scene",
            "renderer",
            "thesis S stated",
            "thesis S from its table",
            "thesis p",
            "thesis e stated",
            "thesis e from its table",
            "ours S",
            "ours p",
            "ours e",
        ],
        rows,
        "lllrrrrrrrr",
        [
            "'stated' is what the thesis' text says; 'from its table' recomputes the metric from its published "
            "times with its own p. Ours: the headline configuration of this run at the same stage and scene."
        ],
    )


def fmt_rate(x: float) -> str:
    """Millions of rays per second, three significant digits (at least the units)."""
    if x is None or not math.isfinite(x):
        return MISSING
    return f"{x:.0f}" if abs(x) >= 100 else f"{x:.3g}"


def summary_table(summary: pd.DataFrame) -> Table:
    """Every configuration with every statistic (warm-up frames excluded),
    and Mrays/s where the runs have counters (metrics.with_throughput)."""
    rate = metrics.MRAYS_PER_S in summary.columns

    def stats(d: dict) -> list[str]:
        return [
            fmt_int(d["n"]),
            fmt_ms(d["median"]),
            f"[{fmt_ms(d['ci_low'])}, {fmt_ms(d['ci_high'])}]",
            *(fmt_ms(d[key]) for key in ("mean", "std", "mad", "p95", "p99")),
            fmt_int(d["outliers"]),
            fmt_int(d["repetitions"]),
            fmt_percent(d["rep_spread"]),
            *([fmt_rate(d[metrics.MRAYS_PER_S])] if rate else []),
        ]

    rows = _config_rows(summary, stats)
    headers, align = _config_headers()
    notes = [
        "n = measured frames over all repetitions; CI = bootstrap 95% CI of the median (2000 resamples, seeded); "
        "outliers = frames with |modified z| > 3.5 (flagged, kept); rep spread = coefficient of variation of the "
        "per-repetition medians."
    ]
    if rate:
        notes.append(MRAYS_NOTE)
        if (summary[metrics.MRAYS_TIME] == names.GPU_MS).any():
            notes.append(GPU_MRAYS_NOTE)
    return Table(
        "summary",
        "Every configuration: render time per frame [ms]",
        [
            *headers,
            *("n", "median", "95% CI", "mean", "std", "MAD", "p95", "p99", "outliers", "reps", "rep spread"),
            *(["Mrays/s"] if rate else []),
        ],
        rows,
        align + "rrlrrrrrrrr" + ("r" if rate else ""),
        notes,
    )


MRAYS_NOTE = (
    "Mrays/s = median over the measured frames of rays / render_ms / 1000: millions of rays (every bounce "
    f"depth) per second of the Render phase, from the --counters runs; {MISSING} = a configuration without counters."
)
GPU_MRAYS_NOTE = (
    "For the gpu renderer Mrays/s divides by gpu_ms instead, the device time of the frame's dispatches "
    "(data/summary.csv's mrays_time names the column used)."
)


# The configuration columns of the lane-occupancy table: what changes the
# counts (threads do not: their tallies are summed).
OCCUPANCY_LEAVE_OUT = ("threads", "target / device")


def lane_occupancy(occupancy: pd.DataFrame) -> Table:
    """The lane work per configuration with counters (metrics.lane_occupancy),
    the SIMD kernel's and the GPU renderer's: rays and node visits per frame,
    each kind's occupancy and the masked share of all of it."""
    rows = []
    for r in occupancy.itertuples(index=False):
        d = r._asdict()
        cells = _config_cells(d, leave_out=OCCUPANCY_LEAVE_OUT)
        rows.append(
            [
                cells[0],
                d[names.EARLY_EXIT],
                *cells[1:],
                fmt_int(round(d[metrics.RAYS_PER_FRAME])),
                fmt_int(round(d[metrics.NODE_VISITS_PER_FRAME])),
                *(fmt_percent(d[metrics.OCCUPANCY[kind]]) for kind in names.LANE_WORK),
                fmt_percent(d[metrics.MASKED_SHARE]),
            ]
        )
    headers, align = _config_headers(leave_out=OCCUPANCY_LEAVE_OUT)
    on_gpu = (occupancy[names.RENDERER] == names.GPU_RENDERER).any()
    return Table(
        "lane-occupancy",
        "Lane occupancy of the SIMD kernel and the GPU's subgroups: the share of lanes doing work that counts"
        if on_gpu
        else "Lane occupancy of the SIMD kernel: the share of vector lanes doing work that counts",
        [
            headers[0],
            "early exits",
            *headers[1:],
            "rays / frame",
            "node visits / frame",
            "node occupancy",
            "sphere-test occupancy",
            "shading occupancy",
            "masked share",
        ],
        rows,
        align[0] + "l" + align[1:] + "rrrrrr",
        [
            "Counters of the measured frames summed per configuration (--counters). rays: every ray that looked for "
            "its nearest sphere, all bounce depths. A node visit is one vector box test (a packet against a box, or "
            "one ray against a wide node's child boxes). Occupancy = lanes active / lane slots of that kind of step: "
            "node visits (rays reaching the box, or child slots holding a child), sphere tests (rays still searching, "
            "or spheres of a leaf) and shading (rays that hit a sphere); "
            f"{MISSING} = no such step. Masked share = 1 - (sum of active lanes) / (sum of lane slots) over all "
            "three: the share of the lane work that was masked off.",
            *([GPU_OCCUPANCY_NOTE] if on_gpu else []),
        ],
    )


GPU_OCCUPANCY_NOTE = (
    "gpu: the lanes are a subgroup's invocations, which run a loop as often as the busiest of them: a kind's slots "
    "are the subgroup size times the busiest invocation's steps in each search (shading: per subgroup and bounce "
    "depth), its active lanes the steps the invocations took (schema/rt_schema.json's counter columns)."
)


def gpu_variants(variants: pd.DataFrame) -> Table:
    """The GPU renderers' variants (metrics.gpu_variants): median gpu_ms of
    each and its speedup over the default variant of the same configuration.
    Where gpu_rt ran, its rows stand beside the gpu renderer's, with the
    renderer and reorder columns and gpu_rt's speedup over the gpu renderer."""
    with_rt = bool((variants[names.RENDERER] == names.GPU_RT_RENDERER).any())
    compute_axes = [axis for axis in names.GPU_AXES if names.takes_axis(names.GPU_RENDERER, axis)]
    axes = names.GPU_AXES if with_rt else compute_axes
    rows = []
    for r in variants.itertuples(index=False):
        d = r._asdict()
        rows.append(
            [
                d[names.STAGE],
                d[names.SCENE],
                *([d[names.RENDERER]] if with_rt else []),
                d[names.ACCEL],
                f"{d[names.WIDTH]}x{d[names.HEIGHT]}",
                *(d[axis] or MISSING for axis in axes),
                fmt_int(d["n"]),
                fmt_ms(d[metrics.GPU_MS_MEDIAN]),
                f"[{fmt_ms(d[metrics.GPU_MS_CI_LOW])}, {fmt_ms(d[metrics.GPU_MS_CI_HIGH])}]",
                fmt_fixed(d[metrics.SPEEDUP_OVER_DEFAULT], 2),
                *([fmt_fixed(d[metrics.SPEEDUP_OVER_GPU], 2)] if with_rt else []),
            ]
        )
    default = " / ".join(names.GPU_AXIS_VALUES[axis][1] for axis in compute_axes)
    devices = sorted({d for d in variants[names.DEVICE] if d})
    notes = [
        "gpu_ms = median device time of the frame's render work (GPU timestamps) "
        "over the measured frames of all repetitions; CI = bootstrap 95% CI of the median. "
        f"× default = the default variant's median ({default}: the one the renderer ran before its variants) "
        f"over this one's, at the same stage, scene, accel and size (> 1: faster), {MISSING} where the default "
        f"did not run. BVH {MISSING}: accel {names.BRUTE_FORCE}, no BVH to walk."
        + (f" Device: {', '.join(devices)}." if devices else "")
    ]
    if with_rt:
        notes.append(GPU_RT_VARIANTS_NOTE)
    return Table(
        "gpu-variants",
        "The GPU renderers' variants: device time per frame [ms]"
        if with_rt
        else "The GPU renderer's variants: device time per frame [ms]",
        [
            "stage",
            "scene",
            *(["renderer"] if with_rt else []),
            names.ACCEL,
            "size",
            "BVH",
            *(["reorder"] if with_rt else []),
            "n",
            "gpu_ms",
            "95% CI",
            "× default",
            *(["× gpu"] if with_rt else []),
        ],
        rows,
        "l" * (2 + with_rt + 2 + len(axes)) + "rrlr" + ("r" if with_rt else ""),
        notes,
    )


GPU_RT_VARIANTS_NOTE = (
    f"{names.GPU_RT_RENDERER}: the Vulkan ray-tracing pipeline on the driver's own acceleration structure (its "
    f"accel is always {names.BVH}; the BVH column is the compute renderer's and does not apply); its "
    f"gpu_ms times the frame's ray traces as the {names.GPU_RENDERER} renderer's times its dispatches. reorder: "
    f"{names.NO_REORDER}, or hit (the invocations reordered by the sphere they hit before shading, "
    f"VK_NV_ray_tracing_invocation_reorder); its × default is over reorder {names.NO_REORDER}. × gpu = the "
    f"{names.GPU_RENDERER} renderer's median in its default variant on its BVH over this one's, at the same "
    f"stage, scene and size (> 1: the ray-tracing pipeline is faster), {MISSING} where that did not run."
)


def thesis_published(thesis_metrics: pd.DataFrame) -> Table:
    """The thesis' stated metrics against its own table, alone (no run needed)."""
    rows = [
        [
            r.stage,
            r.scene,
            r.renderer,
            fmt_ms(r.ref_ms),
            fmt_ms(r.ms),
            fmt_int(r.p),
            fmt_fixed(r.speedup_reported),
            fmt_fixed(r.speedup_recomputed),
            fmt_sig(r.karp_flatt_reported),
            fmt_sig(r.karp_flatt_recomputed),
        ]
        for r in thesis_metrics.itertuples(index=False)
    ]
    reference = names.reference_renderer()
    return Table(
        "thesis-metrics-recomputed",
        "The thesis' metrics: stated vs recomputed from its own published times",
        [
            "stage",
            "scene",
            "renderer",
            f"T {reference} ms",
            "T ms",
            "p",
            "S stated",
            "S recomputed",
            "e stated",
            "e recomputed",
        ],
        rows,
        "lllrrrrrrr",
    )


def startup_vs_spheres(startup: pd.DataFrame) -> Table:
    """Median load, build and prepare time per scene and accel (metrics.startup_times)."""
    rows = [
        [
            str(r[names.SCENE]),
            fmt_int(r[names.SPHERES]),
            str(r[names.ACCEL]),
            fmt_int(r["runs"]),
            fmt_ms(r[names.LOAD_MS]),
            fmt_ms(r[names.BUILD_MS]),
            fmt_ms(r[names.PREPARE_MS]),
        ]
        for r in startup.to_dict("records")
    ]
    return Table(
        "startup-vs-spheres",
        "Before the first frame: median load and build time per scene",
        ["scene", "spheres", "accel", "runs", "load ms", "build ms", "prepare ms"],
        rows,
        "lrlrrrr",
        [
            "load = reading, parsing and checking the scene file (metadata scene.load_ms); build = the acceleration "
            "structure's build (accel_structure.build_ms, none with accel none); prepare = all of the renderer's "
            f"prepare(), the build included. {MISSING}: not recorded (runs from before these times were)."
        ],
    )


def cost_vs_spheres(fits: pd.DataFrame) -> Table:
    """The fitted exponent k of median render_ms = c N^k per configuration
    that ran on several sphere counts (metrics.cost_fits)."""

    def stats(d: dict) -> list[str]:
        return [
            f"{d['spheres_min']}–{d['spheres_max']}",
            fmt_int(d["counts"]),
            fmt_ms(d["ms_min"]),
            fmt_ms(d["ms_max"]),
            fmt_fixed(d["exponent"], 2),
            fmt_fixed(d["r2"], 3),
        ]

    rows = _config_rows(fits, stats, leave_out=("scene",))
    headers, align = _config_headers(leave_out=("scene",))
    return Table(
        "cost-vs-spheres",
        "Cost vs spheres: median render_ms = c N^k, the fitted exponent k",
        [*headers, "spheres N", "counts", "ms at fewest", "ms at most", "k", "R²"],
        rows,
        align + "lrrrrr",
        [
            "k = least-squares slope of log(median render_ms) on log(N) over the configuration's scenes (R² of that "
            "line). Brute force tests every sphere for every ray: expect k near 1. With a BVH a ray visits about "
            "log N tree levels: expect k well under 1; the scene adds to it where a larger cluster covers more "
            "pixels and reflects more rays."
        ],
    )
