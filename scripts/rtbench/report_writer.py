"""Turns benchmark runs into a report: the thesis' tables 1-4 for our run,
the thesis' published numbers beside ours, speedup and Karp-Flatt, figures,
and a README that a person reads first.

    scripts/report.py runs/20250101T120000Z-paper -o report/

Several run directories are pooled (the same configuration in two runs
counts as more repetitions). Warm-up frames are excluded; outliers are
flagged, never dropped. A truncated or corrupted CSV stops the report with an
error naming the file.

What it writes:

    report/README.md          what a person reads first (generated)
    report/tables/*.md|.tex   tables 1-4 of the thesis for our run, the thesis
                              beside ours, metrics, every configuration
    report/plots/*.png|.svg   bars, scaling, frame series, distributions
    report/data/*.csv         summary, metrics and flagged outliers, full precision

The output depends only on the input files (no clock, seeded bootstrap), so
regenerating a report from the same runs gives the same files.
"""

from __future__ import annotations

import argparse
import math
import sys
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd

from rtbench import (
    archive,
    atomic,
    budget,
    cli,
    configurations,
    findings,
    load,
    metrics,
    names,
    noise,
    plots,
    precision,
    stats,
    tables,
    thesis,
    verdicts,
)
from rtbench.run_status import NOT_RUN, RunStatus, probe_reason

TABLES_DIR = "tables"
PLOTS_DIR = "plots"
DATA_DIR = "data"


@dataclass
class ReportInputs:
    """Everything the report is computed from."""

    run_dirs: list[Path]
    frames: pd.DataFrame
    manifests: list[dict | None]  # one per run directory; None where it has none
    thesis_tables: pd.DataFrame
    thesis_reported: pd.DataFrame
    gpu_estimates: list[metrics.GpuEstimate]
    gpu_override: float | None = None
    budgets_ms: tuple[float, ...] = budget.DEFAULT_BUDGETS_MS
    # The line on the runs of retired GPU variants the loader left out (load.load_kept_runs), if any.
    left_out_note: str | None = None


@dataclass
class ReportResults:
    summary: pd.DataFrame
    metrics: pd.DataFrame
    scaling: pd.DataFrame
    curves: pd.DataFrame  # summary rows on a cost-vs-spheres curve (metrics.sphere_curves)
    cost_fits: pd.DataFrame  # one fitted power law per curve (metrics.cost_fits)
    thesis_metrics: pd.DataFrame
    tables: list[tables.Table]
    warnings: list[str]
    budgets: pd.DataFrame = field(default_factory=pd.DataFrame)  # frame-budget statistics (budget.summarize_budgets)
    occupancy: pd.DataFrame = field(default_factory=pd.DataFrame)  # lane counters (metrics.lane_occupancy), if any
    gpu_variants: pd.DataFrame = field(default_factory=pd.DataFrame)  # metrics.gpu_variants, if the run has them
    findings: pd.DataFrame = field(default_factory=pd.DataFrame)  # the thesis' claims with verdicts (findings.evaluate)
    half_precision: pd.DataFrame = field(default_factory=pd.DataFrame)  # precision.half_precision, if the run has f16
    written: list[Path] = field(default_factory=list)


def gather(
    run_dirs: list[Path], gpu_override: float | None = None, budgets_ms: tuple[float, ...] = budget.DEFAULT_BUDGETS_MS
) -> ReportInputs:
    """Loads the runs (strictly: errors name the file) and the thesis' data."""
    run_dirs = [Path(d) for d in run_dirs]
    frames, left_out_note = load.load_kept_runs(run_dirs)
    manifests = [load.read_manifest(d) for d in run_dirs]
    return ReportInputs(
        run_dirs,
        frames,
        manifests,
        thesis.load_tables(),
        thesis.load_reported(),
        metrics.load_gpu_estimates(),
        gpu_override,
        tuple(budgets_ms),
        left_out_note,
    )


def compute(inputs: ReportInputs) -> ReportResults:
    """All statistics, metrics and tables; no I/O. The comparisons see the
    f32 configurations only (names.at_f32); the summary and frame-budget
    tables list every configuration, and the half-precision section sets
    each f16 one beside its f32 twin."""
    summary = metrics.with_throughput(stats.summarize_configs(inputs.frames), inputs.frames)
    f32_summary, f32_frames = names.at_f32(summary), names.at_f32(inputs.frames)
    met, thesis_metrics, occupancy, halves, refusals = check_inputs(inputs, summary)
    scaling = metrics.scaling_table(f32_summary)
    curves = metrics.sphere_curves(f32_summary)
    fits = metrics.cost_fits(curves)
    built = build_tables(summary, met, thesis_metrics, inputs.thesis_tables, fits)
    budgets = budget.summarize_budgets(inputs.frames, inputs.budgets_ms)
    built.append(budget.budget_table(budgets, inputs.budgets_ms))
    if not occupancy.empty:
        built.append(tables.lane_occupancy(occupancy))
    variants = metrics.gpu_variants(f32_frames)
    if not variants.empty:
        built.append(tables.gpu_variants(variants))
    startup = metrics.startup_times(inputs.frames)
    if not fits.empty and not startup.empty:
        built.append(tables.startup_vs_spheres(startup))
    if not halves.empty or refusals:
        built.append(precision.half_precision_table(halves, refusals))
    checked = _findings(inputs, summary, met, thesis_metrics, occupancy, refusals)
    built.append(findings.findings_table(checked))
    warnings = collect_warnings(inputs, summary)
    return ReportResults(
        summary,
        met,
        scaling,
        curves,
        fits,
        thesis_metrics,
        built,
        warnings,
        budgets=budgets,
        occupancy=occupancy,
        gpu_variants=variants,
        findings=checked,
        half_precision=halves,
    )


def check_inputs(inputs: ReportInputs, summary: pd.DataFrame):
    """What the findings need besides the summary: the metrics table and the
    lane occupancy (of the f32 configurations), the thesis' metrics, the
    half-precision table and the f16 probes' refusals."""
    f32_summary = names.at_f32(summary)
    cores = int(inputs.frames[names.LOGICAL_CORES].max())
    met = metrics.metrics_table(f32_summary, cores, inputs.gpu_estimates, inputs.gpu_override)
    thesis_metrics = thesis.reported_vs_recomputed(inputs.thesis_tables, inputs.thesis_reported)
    occupancy = metrics.lane_occupancy(names.at_f32(inputs.frames))
    halves = precision.half_precision(summary, inputs.frames)
    return met, thesis_metrics, occupancy, halves, precision.refused(inputs.manifests)


def build_tables(summary, met, thesis_metrics, thesis_tables, fits) -> list[tables.Table]:
    """Tables 1-4 per image size, then the comparisons (of the f32
    configurations), the cost vs spheres (where the run has it), then
    everything. A thesis table where none of
    its renderers ran at its stage and size is left out (a gpu-only
    1920x1080 leaves table 2, simd_only and tbb_only, empty; a run of
    stage optimized only tables 1-3); the README says which
    (_missing_tables_note)."""
    everything, summary = summary, names.at_f32(summary)
    sizes = tables.sizes(summary if len(summary) else everything)
    scenes = _scene_order(everything, thesis_tables)
    built = []
    for size in sizes:
        for spec in thesis.table_layout(thesis_tables):
            t = tables.thesis_mirror(summary, spec, size, scenes, name_size=len(sizes) > 1)
            if all(cell == tables.MISSING for row in t.rows for cell in row[1:]):
                continue
            built.append(t)
    built.append(tables.side_by_side(summary, thesis_tables, sizes[0]))
    built.append(tables.stage_effects(summary, thesis_tables, sizes[0]))
    built.append(tables.metrics_our(met))
    built.append(tables.metrics_vs_thesis(thesis_metrics, met, sizes[0]))
    built.append(tables.thesis_published(thesis_metrics))
    if not fits.empty:
        built.append(tables.cost_vs_spheres(fits))
    built.append(tables.summary_table(everything))
    return built


def _scene_order(summary: pd.DataFrame, thesis_tables: pd.DataFrame) -> list[str]:
    """The scenes from fewest spheres to most (the thesis' order for its
    own scenes), ties in the thesis' order, then by name."""
    thesis_order = list(pd.unique(thesis_tables["scene"]))
    spheres = summary.groupby(names.SCENE)[names.SPHERES].first()
    return sorted(
        spheres.index, key=lambda s: (spheres[s], thesis_order.index(s) if s in thesis_order else len(thesis_order), s)
    )


def collect_warnings(inputs: ReportInputs, summary: pd.DataFrame) -> list[str]:
    """The runner's machine warnings, plus what the data themselves show."""
    warnings = [w for m in inputs.manifests if m for w in m.get("warnings", [])]
    warnings += [n for d, m in zip(inputs.run_dirs, inputs.manifests) if (n := load.unfinished_note(d, m))]
    warnings += [inputs.left_out_note] if inputs.left_out_note else []
    spreads = {stats.config_label(r): r["rep_spread"] for _, r in summary.iterrows()}
    warnings += noise.spread_warnings(spreads)
    builds = sorted(set(inputs.frames[names.BUILD_TYPE]))
    if any(b.lower() not in ("release", "papero0") for b in builds):
        warnings.append(f"build type {', '.join(builds)}: measure with the release preset (or paper-o0 on purpose)")
    if inputs.frames[names.GIT_DIRTY].any():
        warnings.append("the binary was built from a work tree with uncommitted changes (git_dirty)")
    outliers = int(summary["outliers"].sum())
    if outliers:
        warnings.append(
            f"{outliers} frame(s) flagged as outliers (|modified z| > {stats.OUTLIER_LIMIT}); kept in "
            f"every statistic, listed in {DATA_DIR}/outliers.csv"
        )
    return list(dict.fromkeys(warnings))


# --- the command (scripts/report.py, python3 -m rtbench report) ---------------------


def main(argv: list[str] | None = None, prog: str | None = None) -> int:
    parser = cli.command_parser(prog, __doc__)
    parser.add_argument(
        "run_dirs",
        nargs="+",
        type=Path,
        metavar="RUN_DIR",
        help="run directory written by scripts/bench, or a run archive (.tar.xz, data/reference-runs/README.md)",
    )
    parser.add_argument(
        "-o",
        "--output",
        type=Path,
        help="report directory (default: report/); with --findings the Markdown file (default: standard output)",
    )
    parser.add_argument(
        "--findings",
        action="store_true",
        help="instead of a report: the thesis' findings of each run side by side, one column per run (not pooled)",
    )
    parser.add_argument(
        "--gpu-p",
        type=float,
        metavar="N",
        help="processor count of the GPU for Karp-Flatt (default: per-device estimate, data/gpu_processors.toml)",
    )
    budget.add_budgets_option(parser, "frame budgets of the frame-budget table")
    parser.add_argument("-q", "--quiet", action="store_true", help="print nothing but errors")
    args = parser.parse_args(argv)
    if args.gpu_p is not None and args.gpu_p <= 1:
        parser.error("--gpu-p must be greater than 1")
    if not all(math.isfinite(b) and b > 0 for b in args.budget_ms):
        parser.error("--budget-ms must be positive numbers of milliseconds")

    if args.findings:
        return findings_side_by_side(parser.prog, args)
    args.output = args.output or Path("report")
    try:
        with archive.unpacked(args.run_dirs) as run_dirs:  # a committed run archive reads as its directory
            inputs = gather(run_dirs, args.gpu_p, tuple(args.budget_ms))
            results = compute(inputs)
            written = write(inputs, results, args.output)
    except (load.RunDataError, thesis.ThesisDataError) as e:
        print(f"{parser.prog}: {e}", file=sys.stderr)
        return 1
    if not args.quiet:
        print(f"report: {args.output / 'README.md'} ({len(written)} files, {len(results.summary)} configurations)")
        for w in results.warnings:
            print(f"warning: {w}", file=sys.stderr)
    return 0


def findings_side_by_side(prog: str, args: argparse.Namespace) -> int:
    """--findings: the verdicts table of the runs (rtbench.verdicts), to -o or standard output."""
    try:
        with archive.unpacked(args.run_dirs) as run_dirs:
            columns = []
            for run_dir in run_dirs:
                inputs = gather([run_dir], args.gpu_p)
                columns.append((verdicts.run_label(run_dir, inputs.frames), evaluate_findings(inputs)))
    except (load.RunDataError, thesis.ThesisDataError) as e:
        print(f"{prog}: {e}", file=sys.stderr)
        return 1
    text = verdicts.side_by_side(columns)
    if args.output is None:
        print(text, end="")
        return 0
    atomic.write_text(args.output, text)
    if not args.quiet:
        print(f"findings: {args.output} ({len(columns)} runs)")
    return 0


def evaluate_findings(inputs: ReportInputs) -> pd.DataFrame:
    """The findings of one run (findings.COLUMNS), as its report computes them."""
    summary = stats.summarize_configs(inputs.frames)
    met, thesis_metrics, occupancy, _, refusals = check_inputs(inputs, summary)
    return _findings(inputs, summary, met, thesis_metrics, occupancy, refusals)


def _findings(inputs: ReportInputs, summary, met, thesis_metrics, occupancy, refusals) -> pd.DataFrame:
    """findings.evaluate at the run's first image size of its f32 configurations
    (of any, in a run of f16 only)."""
    f32 = names.at_f32(summary)
    size = tables.sizes(f32 if len(f32) else summary)[0]
    return findings.evaluate(
        summary, inputs.frames, met, inputs.thesis_tables, thesis_metrics, size, occupancy, refusals
    )


# --- writing ---------------------------------------------------------------------


def write(inputs: ReportInputs, results: ReportResults, out: Path) -> list[Path]:
    """Writes every file of the report, then removes stale files that an
    earlier report left in the directories this one owns."""
    out = Path(out)
    written = []
    for t in results.tables:
        written.append(atomic.write_text(out / TABLES_DIR / f"{t.slug}.md", tables.to_markdown(t)))
        written.append(atomic.write_text(out / TABLES_DIR / f"{t.slug}.tex", tables.to_latex(t)))
    written += write_data(inputs, results, out / DATA_DIR)
    figures = draw_figures(inputs, results, out / PLOTS_DIR)
    written += [p for paths in figures.values() for p in paths]
    written.append(atomic.write_text(out / "README.md", readme(inputs, results, figures, out)))
    remove_stale(out, written)
    results.written = written
    return written


def write_data(inputs: ReportInputs, results: ReportResults, out: Path) -> list[Path]:
    """Full-precision CSVs of the summary, the metrics and the outliers."""
    frames = inputs.frames.assign(modified_z=stats.modified_z_by_config(inputs.frames))
    flagged = frames[frames["modified_z"].abs() > stats.OUTLIER_LIMIT]
    outlier_cols = [names.SOURCE, names.FRAME, names.SCENE, names.RENDERER, names.STAGE, names.RENDER_MS, "modified_z"]
    files = {
        "summary.csv": results.summary,
        "metrics.csv": results.metrics,
        "outliers.csv": flagged[outlier_cols],
        "thesis_metrics.csv": results.thesis_metrics,
    }
    if not results.findings.empty:
        files["thesis_findings.csv"] = results.findings
    if not results.cost_fits.empty:
        files["cost_vs_spheres.csv"] = results.cost_fits
    files["budget.csv"] = results.budgets
    if not results.occupancy.empty:
        files["lane_occupancy.csv"] = results.occupancy
    if not results.gpu_variants.empty:
        files["gpu_variants.csv"] = results.gpu_variants
    if not results.half_precision.empty:
        files["half_precision.csv"] = results.half_precision
    return [atomic.write_text(out / name, df.to_csv(index=False, float_format="%.17g")) for name, df in files.items()]


def draw_figures(inputs: ReportInputs, results: ReportResults, out: Path) -> dict[str, list[Path]]:
    """Every figure; an empty list where the run has no data for one."""
    frames = names.at_f32(inputs.frames)
    return {
        "render_ms": plots.render_bars(names.at_f32(results.summary), out / "render_ms"),
        "thesis_speedups": plots.thesis_speedups(_speedup_pairs(results, inputs), out / "thesis_speedups"),
        "scaling": plots.speedup_vs_threads(results.scaling, out / "scaling"),
        "karp_flatt": plots.karp_flatt_vs_p(results.metrics, out / "karp_flatt"),
        "cost_vs_spheres": plots.cost_vs_spheres(results.curves, results.cost_fits, out / "cost_vs_spheres"),
        "frame_series": plots.frame_series(frames, out / "frame_series"),
        "distributions": plots.distributions(frames, out / "distributions"),
    }


def _speedup_pairs(results: ReportResults, inputs: ReportInputs) -> pd.DataFrame:
    """Thesis vs our speedups for the largest thesis scene in our run."""
    published = thesis.recomputed_speedups(inputs.thesis_tables)
    ours = tables.headline_rows(results.metrics) if not results.metrics.empty else results.metrics
    scenes = [s for s in pd.unique(published["scene"]) if not ours.empty and s in set(ours[names.SCENE])]
    if not scenes:
        return pd.DataFrame(columns=["renderer", "stage", "scene", "thesis", "ours"])
    scene = scenes[-1]
    rows = []
    for r in published[published["scene"] == scene].itertuples(index=False):
        hit = ours[(ours[names.SCENE] == scene) & (ours[names.RENDERER] == r.renderer) & (ours[names.STAGE] == r.stage)]
        rows.append(
            {
                "renderer": r.renderer,
                "stage": r.stage,
                "scene": scene,
                "thesis": r.speedup,
                "ours": hit["speedup"].iloc[0] if len(hit) else math.nan,
            }
        )
    return pd.DataFrame(rows)


def remove_stale(out: Path, written: list[Path]) -> None:
    keep = {p.resolve() for p in written}
    for sub in (TABLES_DIR, PLOTS_DIR, DATA_DIR):
        for path in (out / sub).glob("*"):
            if path.is_file() and path.resolve() not in keep:
                path.unlink()


# --- README ------------------------------------------------------------------------


def readme(inputs: ReportInputs, results: ReportResults, figures: dict[str, list[Path]], out: Path) -> str:
    """report/README.md: what ran, warnings, how to read it, the tables, figures."""
    by_slug = {t.slug: t for t in results.tables}
    parts = [
        "# Benchmark report\n",
        "Generated by `scripts/report.py` from the run(s) below; do not edit by hand, regenerate it.\n",
        _what_ran(inputs, results),
        _warnings_section(results.warnings),
        how_to_read(results.summary),
        "## The thesis' tables 1-4, for our run\n",
        *(tables.to_markdown(t) for t in results.tables if t.slug.startswith("table")),
        _missing_tables_note(inputs.thesis_tables, results.tables),
        _findings_section(by_slug),
        "## The thesis beside ours\n",
        tables.to_markdown(by_slug["thesis-vs-ours"]),
        _figure(figures, "thesis_speedups", "Speedups: thesis vs ours", out),
        "## What the stages change\n",
        tables.to_markdown(by_slug["stage-effects"]),
        "## Speedup and Karp-Flatt\n",
        tables.to_markdown(by_slug["metrics-vs-thesis"]),
        tables.to_markdown(by_slug["metrics"]),
        _figure(figures, "karp_flatt", "Karp-Flatt e against p = threads x lanes", out),
        "## The thesis' own metrics, recomputed\n",
        thesis_note(results.thesis_metrics),
        tables.to_markdown(by_slug["thesis-metrics-recomputed"]),
        _cost_section(by_slug, figures, out),
        _gpu_variants_section(by_slug),
        _half_precision_section(by_slug),
        _occupancy_section(by_slug, results.occupancy),
        "## Frame budget\n",
        tables.to_markdown(by_slug["frame-budget"]),
        "## Figures\n",
        _figure(figures, "render_ms", "Render time per frame", out),
        _figure(figures, "scaling", "Strong scaling", out)
        or "No strong-scaling figure: this run has one thread count per renderer (use `--profile scaling`).\n",
        ""
        if figures.get("cost_vs_spheres")
        else f"No cost-vs-spheres figure: no configuration of this run ran on {metrics.MIN_SPHERE_COUNTS} or more "
        "sphere counts (use `--profile scene-size`).\n",
        _figure(figures, "frame_series", "Frame times in run order", out),
        _figure(figures, "distributions", "Frame-time distributions", out),
        "## Every configuration\n",
        f"All statistics of every configuration: [`{TABLES_DIR}/summary.md`]({TABLES_DIR}/summary.md); "
        f"full precision in [`{DATA_DIR}/summary.csv`]({DATA_DIR}/summary.csv), "
        f"[`{DATA_DIR}/metrics.csv`]({DATA_DIR}/metrics.csv), flagged frames in "
        f"[`{DATA_DIR}/outliers.csv`]({DATA_DIR}/outliers.csv). LaTeX versions of every table are beside the "
        f"Markdown ones in `{TABLES_DIR}/` (they need `\\usepackage{{booktabs}}`).\n",
        _unfinished_section(inputs.run_dirs, inputs.manifests),
    ]
    return "\n".join(p for p in parts if p)


def _findings_section(by_slug: dict[str, tables.Table]) -> str:
    """Each of the thesis' claims as a predicate over this run, with its verdict (findings.py)."""
    if "thesis-findings" not in by_slug:
        return ""
    return "\n".join([f"## {findings.TITLE}\n", FINDINGS_TEXT, tables.to_markdown(by_slug["thesis-findings"])])


FINDINGS_TEXT = """What the thesis concluded from its tables (docs/thesis.md, "What the tables
show"), each claim a figure of this run with its 95 % bootstrap CI, the region
in which the claim holds, and a verdict; where ours differs, what in the
run's metadata (optimisation, cores, vector width) or lane counters may say
why. Compare the verdicts, not the times: the thesis measured at -O0 on an
Apple M1. [`data/thesis_findings.csv`](data/thesis_findings.csv) has the
figures at full precision.
"""


def _missing_tables_note(thesis_tables: pd.DataFrame, built: list[tables.Table]) -> str:
    """Which thesis tables build_tables left out: none of their renderers ran
    at their stage, at any size."""
    shown = {t.slug.split("-")[0] for t in built}
    missing = [spec for spec in thesis.table_layout(thesis_tables) if f"table{spec.number}" not in shown]
    if not missing:
        return ""
    which = ", ".join(f"{spec.number} ({spec.stage}: {', '.join(spec.renderers)})" for spec in missing)
    noun = "tables" if len(missing) > 1 else "table"
    return f"Not shown, since none of their renderers ran at their stage in this run: {noun} {which}.\n"


def _cost_section(by_slug: dict[str, tables.Table], figures: dict[str, list[Path]], out: Path) -> str:
    """How the render time grows with the sphere count, where the run has
    configurations on enough sphere counts to fit it."""
    if "cost-vs-spheres" not in by_slug:
        return ""
    parts = [
        "## Cost vs spheres\n",
        tables.to_markdown(by_slug["cost-vs-spheres"]),
        _figure(figures, "cost_vs_spheres", "Cost vs spheres (log-log, fitted power laws)", out),
    ]
    if "startup-vs-spheres" in by_slug:
        parts.append(tables.to_markdown(by_slug["startup-vs-spheres"]))
    return "\n".join(parts)


def _gpu_variants_section(by_slug: dict[str, tables.Table]) -> str:
    """The GPU renderer's variants side by side, where the run has more than
    the default one, and gpu_rt beside them where it ran."""
    if "gpu-variants" not in by_slug:
        return ""
    table = by_slug["gpu-variants"]
    text = GPU_VARIANTS_TEXT + (GPU_RT_TEXT if "renderer" in table.headers else "")
    return "\n".join([f"## {GPU_VARIANTS_TITLE}\n", text, tables.to_markdown(table)])


GPU_VARIANTS_TITLE = "GPU traversal variants"
GPU_VARIANTS_TEXT = """The GPU renderer in each of its variants: the structure its shader walks
(`binary`, `wide`: the 8-wide tree, or `grid`: a uniform grid of cells, which
is not a tree), compared by their device time (gpu_ms), not render_ms: the
host's time around a submit and a wait is mostly not the tracing at these
frame times. Descriptions: schema/rt_schema.json's gpu_bvhs.
"""
GPU_RT_TEXT = """
Beside them the gpu_rt renderer: the Vulkan ray-tracing pipeline
(VK_KHR_ray_tracing_pipeline) tracing the same rays through the driver's own
acceleration structure (on NVIDIA's devices walked by the RT cores), the
sphere test in its intersection shader; with reorder `hit` the invocations
are reordered by the sphere they hit before shading
(VK_NV_ray_tracing_invocation_reorder). Its × gpu column compares it with the
gpu renderer's default variant on its BVH at the same stage, scene and size.
"""


def _half_precision_section(by_slug: dict[str, tables.Table]) -> str:
    """The f16 configurations beside their f32 twins, where the run has
    them or the bench's probe refused them."""
    if precision.SLUG not in by_slug:
        return ""
    return "\n".join([f"## {precision.TITLE}\n", HALF_PRECISION_TEXT, tables.to_markdown(by_slug[precision.SLUG])])


HALF_PRECISION_TEXT = """The thesis tried halving the SIMD precision between its first two stages
(eight f16 lanes per register instead of four f32 ones) and dropped it: twice
as fast, but the image unusable (docs/thesis.md, "Stages"). Here each f16
configuration runs beside its f32 twin, and each image of frame 0 is compared
with the double-precision reference under the rule every renderer is tested
by. [`data/half_precision.csv`](data/half_precision.csv) has the figures at
full precision; claim 8 of the findings is the verdict.
"""


OCCUPANCY_TITLE = "Lane occupancy (the thesis' masking waste, measured)"
# Above this masked share most of the vector work is thrown away: the thesis' hypothesis holds.
MOSTLY_MASKED = 0.5


def _occupancy_section(by_slug: dict[str, tables.Table], occupancy: pd.DataFrame) -> str:
    """The lane counters against the thesis' hypothesis, where the run has counters."""
    if "lane-occupancy" not in by_slug:
        return ""
    return "\n".join(
        [f"## {OCCUPANCY_TITLE}\n", occupancy_statement(occupancy), tables.to_markdown(by_slug["lane-occupancy"])]
    )


def occupancy_statement(occupancy: pd.DataFrame) -> str:
    """What the masked shares say about the thesis' hypothesis, with this run's range."""
    shares = occupancy.dropna(subset=[metrics.MASKED_SHARE])
    text = (
        "The thesis concluded that SIMD suits this ray tracer poorly because, with much branching, most masked "
        "lanes do wasted work (docs/thesis.md). The SIMD kernel's counters put a number on it: every vector step "
        "occupies all its lanes, and the masked share is the part of them whose work was thrown away. 0% would be "
        f"SIMD without waste; above {MOSTLY_MASKED:.0%} most of the vector work is wasted, as the thesis supposed. "
    )
    if (occupancy[names.RENDERER] == names.GPU_RENDERER).any():
        text += GPU_OCCUPANCY_TEXT
    if shares.empty:
        return text + "No configuration of this run recorded a vector step.\n"
    low = shares.loc[shares[metrics.MASKED_SHARE].idxmin()]
    high = shares.loc[shares[metrics.MASKED_SHARE].idxmax()]
    mostly = int((shares[metrics.MASKED_SHARE] > MOSTLY_MASKED).sum())
    return text + (
        f"Here {mostly} of {len(shares)} configurations mask off more than {MOSTLY_MASKED:.0%} of their lane work; "
        f"the share ranges from {tables.fmt_percent(low[metrics.MASKED_SHARE])} ({stats.config_label(low)}) to "
        f"{tables.fmt_percent(high[metrics.MASKED_SHARE])} ({stats.config_label(high)}).\n"
    )


GPU_OCCUPANCY_TEXT = (
    "On the GPU a subgroup (a warp) runs its invocations in lockstep, the same waste in another form: a loop "
    "runs as often as its busiest invocation, and the others' lanes idle; the GPU renderer's counters measure "
    "that share per subgroup. "
)


def _what_ran(inputs: ReportInputs, results: ReportResults) -> str:
    frames = inputs.frames
    lines = ["## What ran\n", "| | |", "|:--|:--|"]
    for d, m in zip(inputs.run_dirs, inputs.manifests, strict=True):
        profile = (m or {}).get("profile", {}).get("name", "(no manifest)")
        lines.append(f"| run | `{d.name}` (profile `{profile}`) |")
    lines.append(
        f"| CPU | {', '.join(sorted(set(frames[names.CPU_MODEL])))} "
        f"({', '.join(map(str, sorted(set(frames[names.LOGICAL_CORES]))))} logical cores) |"
    )
    devices = sorted({d for d in frames[names.DEVICE] if d})
    if devices:
        lines.append(f"| Vulkan device | {', '.join(devices)} |")
    commits = sorted(
        {f"{c[:12]}{' (dirty)' if d else ''}" for c, d in zip(frames[names.GIT_COMMIT], frames[names.GIT_DIRTY])}
    )
    lines.append(f"| build | {', '.join(sorted(set(frames[names.BUILD_TYPE])))}, commit {', '.join(commits)} |")
    s = results.summary
    lines.append(
        f"| configurations | {len(s)}, {int(s['n'].sum())} measured frames "
        f"({int(frames[names.WARMUP].sum())} warm-up frames excluded) |"
    )
    lines.append(f"| image sizes | {', '.join(f'{w}x{h}' for w, h in tables.sizes(s))} |")
    return "\n".join(lines) + "\n"


def _warnings_section(warnings: list[str]) -> str:
    if not warnings:
        return "## Warnings\n\nNone: governor, load, spread between repetitions and build type look fine.\n"
    return "## Warnings\n\n" + "\n".join(f"- {w}" for w in warnings) + "\n"


def _figure(figures: dict[str, list[Path]], key: str, caption: str, out: Path) -> str:
    paths = figures.get(key) or []
    png = [p for p in paths if p.suffix == ".png"]
    if not png:
        return ""
    rel = png[0].relative_to(out).as_posix()
    svg = rel[:-4] + ".svg"
    return f"![{caption}]({rel})\n\n*{caption}* ([SVG]({svg}))\n"


def _unfinished_section(run_dirs: list[Path], manifests: list[dict | None]) -> str:
    """Runs that did not produce data: configurations an unfinished run has
    not run yet (one line each), renderers (or a probed option of one) whose
    probe failed (one line each, with the probe's reason), failures (one line
    per run)."""
    rows = [r for m in manifests if m for r in m.get("runs", []) if r.get("status") not in (RunStatus.OK, *NOT_RUN)]
    missing = [(d, c, reps) for d, m in zip(run_dirs, manifests) if m for c, reps in load.missing_runs(m).items()]
    if not rows and not missing:
        return ""
    lines = ["## Runs without data\n", "| run | status | exit | reason |", "|:--|:--|--:|:--|"]
    for run_dir, config, reps in missing:
        lines.append(
            f"| {config} {' '.join(f'r{r}' for r in reps)} | missing (the run was stopped) | | "
            f"`scripts/bench --resume {run_dir}` runs it |"
        )
    for r in rows:
        if r.get("status") == RunStatus.UNAVAILABLE:
            continue
        lines.append(
            f"| {r.get('config')} r{r.get('repetition')} | {r.get('status')} | "
            f"{'' if r.get('exit_code') is None else r.get('exit_code')} | {_reason(r)} |"
        )
    skipped = [_skipped_line(what, runs) for what, runs in _skipped_groups(manifests).items()]
    lines += skipped
    return "\n".join(lines) + "\n" + (SKIPPED_NOTE if skipped else "")


SKIPPED_NOTE = """
Skipped: before its runs the bench tries each renderer on one 4x4 frame
(gpu_rt also with each `--gpu-rt-reorder` value its runs use); where that
probe fails, the runs it stands for are not started, and the reason above is
what the probe said: a binary built without the renderer, no usable Vulkan
device, or a device without the extensions the renderer needs (gpu_rt:
VK_KHR_acceleration_structure and VK_KHR_ray_tracing_pipeline; its hit
reordering: VK_NV_ray_tracing_invocation_reorder, which only NVIDIA's
devices offer). Such a renderer is missing from every table of this report.
"""


def _skipped_groups(manifests: list[dict | None]) -> dict[tuple[str, str, str], list[dict]]:
    """The unavailable runs by (renderer, the probed options of their
    configuration: configurations.probe_args, the probe's reason); the label
    of a group says 'every RENDERER run' where it holds all of the renderer's
    runs, else names the options."""
    groups: dict[tuple[str, str, str], list[dict]] = {}
    totals: dict[str, int] = {}
    for m in manifests:
        if not m:
            continue
        configs = {c.get("id"): c for c in m.get("configs", [])}
        for r in m.get("runs", []):
            renderer = r.get("renderer", "?")
            totals[renderer] = totals.get(renderer, 0) + 1
            if r.get("status") != RunStatus.UNAVAILABLE:
                continue
            options = " ".join(configurations.probe_args(configs.get(r.get("config")) or {}))
            groups.setdefault((renderer, options, probe_reason(r)), []).append(r)
    by_renderer: dict[str, int] = {}
    for (renderer, _, _), runs in groups.items():
        by_renderer[renderer] = by_renderer.get(renderer, 0) + len(runs)
    merged: dict[tuple[str, str, str], list[dict]] = {}
    for (renderer, options, reason), runs in groups.items():
        whole = by_renderer[renderer] == totals[renderer]
        merged.setdefault((renderer, "" if whole else options, reason), []).extend(runs)
    return merged


def _skipped_line(what: tuple[str, str, str], runs: list[dict]) -> str:
    renderer, options, reason = what
    which = f"every {renderer} run" + (f" with `{options}`" if options else "")
    cell = reason.replace("|", "\\|")
    return f"| {which} ({len(runs)}) | skipped: its probe failed | | {cell} |"


def _reason(run: dict) -> str:
    return " ".join((run.get("stderr_tail") or "").split())[-200:].replace("|", "\\|")


def how_to_read(summary: pd.DataFrame) -> str:
    """HOW_TO_READ, and what the run's traversals, GPU variants and counters
    add to the tables where it has them."""
    extra = []
    if any(names.traversal_tag(t) for t in summary[names.TRAVERSAL]):
        extra.append(TRAVERSAL_NOTE)
    if metrics.has_gpu_variants(summary):
        extra.append(GPU_VARIANTS_NOTE)
    if (summary[names.RENDERER] == names.GPU_RT_RENDERER).any():
        extra.append(GPU_RT_NOTE)
    if metrics.MRAYS_PER_S in summary.columns:
        extra.append(COUNTERS_NOTE)
        if (summary[metrics.MRAYS_TIME] == names.GPU_MS).any():
            extra.append(GPU_COUNTERS_NOTE)
    return HOW_TO_READ + "".join(extra)


TRAVERSAL_NOTE = """- The accel column names the traversal where the SIMD kernel walked the BVH
  otherwise than in packets (`bvh single`: each ray alone through a wide BVH;
  `bvh hybridN`: packets until at most N lanes reach a node, then single
  rays); plain `bvh` is packets, the only way before the traversal axis.
"""
GPU_VARIANTS_NOTE = """- The accel column names the GPU renderer's walk where it is not the default
  (the binary BVH): `bvh wide` walks the 8-wide BVH, `bvh grid` the grid.
  Tables 1-4 and the comparisons with the thesis show the default walk; the
  GPU section compares them all.
"""
GPU_RT_NOTE = """- gpu_rt (the ray-tracing pipeline) always walks the driver's own structure:
  its accel is `bvh`, and `bvh hit-reorder` where it reordered its hits
  before shading. Like the gpu renderer's, its render_ms is host time
  around a submit and a wait; the GPU section compares the device times.
"""
GPU_COUNTERS_NOTE = """- The gpu renderer's **Mrays/s** divides by gpu_ms, the device time of the
  frame's dispatches, instead of render_ms (the host's time around them).
"""
COUNTERS_NOTE = """- Runs with `--counters` add **Mrays/s** to the summary table: the median
  over the measured frames of rays / render_ms / 1000, where rays counts every
  ray traced in the frame at every bounce depth; more is faster. Counting
  itself costs time, so compare render times of runs without it. The
  lane-occupancy section shows what their counters say about the SIMD lanes.
"""

HOW_TO_READ = """## How to read this report

- Every number is a statistic of the **measured** frames of a configuration
  (one scene x renderer x stage x accel x threads x lanes x size), all repetitions
  pooled; warm-up frames are never included. The tables show the **median**
  render time per frame (`render_ms`, host wall time of the Render phase).
- The thesis reported arithmetic means at -O0 on an Apple M1; times do not
  compare across machines, **speedups** over the sequential reference do.
- Where a renderer ran with several thread counts or lane widths, tables 1-4,
  the comparisons and the render-time figure show the configuration with the
  most threads x lanes; all of them are in the summary table, the scaling
  and Karp-Flatt figures. Tables 1-4 show brute force (accel `none`), the
  thesis' algorithm; other accels are in the summary.
- Uncertainty: the 95 % bootstrap confidence interval of the median (seeded,
  so a report regenerates identically) and the spread between repetitions.
  Frames with a modified z-score above 3.5 are flagged as outliers, never
  dropped.
- Karp-Flatt e = (1/S - 1/p)/(1 - 1/p) estimates the serial fraction: small
  and flat as p grows means the work parallelises well. p = threads x lanes
  for the CPU renderers (from each run's metadata); for the GPU, a per-device
  estimate of its FP32 lanes (`data/gpu_processors.toml`, or `--gpu-p`).
"""


def thesis_note(thesis_metrics: pd.DataFrame) -> str:
    """Says, with the numbers, that the thesis' Karp-Flatt values do not
    follow from its own table while its speedups do."""
    kf = thesis_metrics.dropna(subset=["karp_flatt_reported"])
    off = [
        f"{r.stage} {r.renderer} on {r.scene}: stated {tables.fmt_sig(r.karp_flatt_reported)}, "
        f"recomputed {tables.fmt_sig(r.karp_flatt_recomputed)} (p = {int(r.p)})"
        for r in kf.itertuples(index=False)
        if not math.isclose(r.karp_flatt_reported, r.karp_flatt_recomputed, rel_tol=0.02)
    ]
    s_ok = all(
        math.isclose(a, b, rel_tol=1e-3)
        for a, b in zip(thesis_metrics["speedup_reported"], thesis_metrics["speedup_recomputed"])
        if math.isfinite(a)
    )
    text = "The thesis' speedups " + ("follow from" if s_ok else "do not all follow from") + " its published times. "
    if off:
        text += (
            "Its Karp-Flatt values do not: with its own p and its own times they come out as follows, and "
            "this report uses the recomputed values wherever it compares with the thesis.\n\n"
            + "\n".join(f"- {o}" for o in off)
            + "\n"
        )
    else:
        text += "Its Karp-Flatt values follow from them too.\n"
    return text
