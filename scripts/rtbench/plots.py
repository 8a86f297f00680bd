"""The report's figures (matplotlib, Agg backend: no display, no plt.show()).

Each function draws one figure from the summary or the tidy frames and saves
it as PNG and SVG (atomically); it returns the paths written, or [] when the
run has no data for that figure (e.g. no thread scaling in a `quick` run).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import matplotlib.ticker
import numpy as np
import pandas as pd

from rtbench import atomic, metrics, names, stats, tables

FORMATS = ("png", "svg")
# Stable SVG ids and no timestamps: the same data give byte-identical files.
plt.rcParams.update({"svg.hashsalt": "rtbench", "figure.dpi": 100, "savefig.dpi": 110, "font.size": 9})


def save(fig, stem: Path) -> list[Path]:
    """Writes stem.png and stem.svg, each via a temporary file."""
    paths = []
    fig.tight_layout()  # once: both formats share the layout
    for fmt in FORMATS:
        path = stem.with_suffix(f".{fmt}")
        with atomic.atomic_path(path) as tmp:
            fig.savefig(tmp, format=fmt, metadata={"Date": None} if fmt == "svg" else {"Software": None})
        paths.append(path)
    plt.close(fig)
    return paths


def _log_y(ax, values, pad: float = 1.0) -> None:
    """Log y axis with plain numbers (0.5, 2, 40, not 5x10^-1); over less than
    three decades also 2x and 5x ticks, so a narrow panel still has labels.
    `pad` > 1 sets the limits to the data's range widened by that factor."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v) & (v > 0)]
    ax.set_yscale("log")
    if v.size and np.log10(v.max() / v.min()) < 3:
        ax.yaxis.set_major_locator(matplotlib.ticker.LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
    ax.yaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda y, _: f"{y:g}"))
    ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    if v.size and pad > 1:
        ax.set_ylim(v.min() / pad, v.max() * pad)


def _ordered(values, order) -> list:
    return sorted(pd.unique(values), key=lambda v: (order(v), str(v)))


def _renderer_label(row, with_size: bool = False) -> str:
    """Renderer plus the threads and lanes where it takes them, the accel
    where it is not brute force, and the image size where the figure holds
    several: 'simd_tbb t8 l16', 'simd_tbb t8 l16 bvh', 'gpu 1920x1080'."""
    size = [f"{row[names.WIDTH]}x{row[names.HEIGHT]}"] if with_size else []
    return " ".join([row[names.RENDERER], *_option_texts(row), *names.accel_tag(row), *size])


def _several_sizes(df: pd.DataFrame) -> bool:
    """Whether the data hold more than one image size: then a label names it
    (the gpu at 800x600 and at 1920x1080 are two configurations)."""
    return len(df[[names.WIDTH, names.HEIGHT]].drop_duplicates()) > 1


def _palette(count: int):
    """Distinct colours for up to 20 lines or bars (tab10, else tab20); they
    repeat only beyond that."""
    cmap = plt.get_cmap("tab10" if count <= 10 else "tab20")
    return lambda i: cmap(i % cmap.N)


def _option_texts(row) -> list[str]:
    """The threads and lanes where the row's renderer takes them: ['t8', 'l16']."""
    return [f"{option[0]}{value}" for option, value in names.label_options(row)]


def render_bars(summary: pd.DataFrame, stem: Path) -> list[Path]:
    """Median render_ms per renderer x scene, one panel per stage, log scale,
    with the bootstrap CI of the median as error bars. One bar per renderer,
    accel and size: its configuration with the most threads x lanes, as in
    tables 1-4 (the other thread counts and lane widths are in the scaling
    and Karp-Flatt figures)."""
    if summary.empty:
        return []
    df = bar_rows(summary)
    stages_ = _ordered(df[names.STAGE], names.stage_order)
    scenes = _scenes_by_size(df)
    labels = _ordered(df["_label"], lambda text: names.renderer_order(text.split(" ")[0]))
    panel = max(4.2, 0.12 * len(labels) * len(scenes))  # inches: room for every bar and scene name
    fig, axes = plt.subplots(1, len(stages_), figsize=(panel * len(stages_) + 1, 3.8), sharey=True, squeeze=False)
    width = 0.8 / max(len(labels), 1)
    colors = _palette(len(labels))
    for ax, stage in zip(axes[0], stages_):
        part = df[df[names.STAGE] == stage]
        for i, label in enumerate(labels):
            _bars(
                ax,
                part[part["_label"] == label],
                scenes,
                (i - (len(labels) - 1) / 2) * width,
                width,
                label=label,
                color=colors(i),
            )
        _log_y(ax, np.concatenate([df["ci_low"].to_numpy(dtype=float), df["ci_high"].to_numpy(dtype=float)]), pad=1.6)
        ax.set_title(f"stage {stage}")
        ax.set_xticks(np.arange(len(scenes)), scenes)
        ax.grid(axis="y", which="both", alpha=0.3)
    axes[0][0].set_ylabel("render_ms per frame (median, log scale)")
    handles = {h.get_label(): h for ax in axes[0] for h in ax.get_legend_handles_labels()[0]}
    axes[0][-1].legend(
        [handles[label] for label in labels if label in handles],
        [label for label in labels if label in handles],
        fontsize=7,
        loc="upper left",
        bbox_to_anchor=(1.02, 1),
    )
    fig.suptitle(f"Render time per frame ({_size_text(df)})")
    return save(fig, stem)


def bar_rows(summary: pd.DataFrame) -> pd.DataFrame:
    """The configurations render_bars draws, with their legend label in
    `_label`: per scene, renderer, stage, accel and size the one with the
    most threads x lanes."""
    widest = tables.widest_rows(summary)
    return widest.assign(_label=widest.apply(_renderer_label, axis=1, with_size=_several_sizes(widest)))


def _bars(ax, rows: pd.DataFrame, scenes: list[str], offset: float, width: float, **style) -> None:
    """One configuration's bars over the scenes it ran (a scene it did not
    run gets no bar, not a NaN one), with the median's CI as error bars."""
    rows = rows.set_index(names.SCENE)
    at = [k for k, scene in enumerate(scenes) if scene in rows.index]
    if not at:
        return
    hit = rows.loc[[scenes[k] for k in at]]
    med, lo, hi = (hit[c].to_numpy(dtype=float) for c in ("median", "ci_low", "ci_high"))
    x = np.array(at) + offset
    ax.bar(x, med, width, **style)
    # The error bars as ax.bar(yerr=...) draws them (black, on the bars'
    # centres and tops, no legend entry), but by errorbar itself with one
    # 2 x N array: bar hands errorbar a list of N-element arrays, in which
    # matplotlib 3.7+ looks for a finite element with math.isfinite, which
    # NumPy 1.25+ deprecates for a one-element array (a configuration with a
    # bar in one scene only). Same figure, the same bytes under matplotlib 3.6.
    ax.errorbar(x, med, yerr=np.vstack([med - lo, hi - med]), fmt="none", ecolor="k", capsize=2, label="_nolegend_")


def _scenes_by_size(df: pd.DataFrame) -> list[str]:
    """The scenes from fewest spheres to most (then by name)."""
    counts = df.groupby(names.SCENE)[names.SPHERES].first()
    return sorted(counts.index, key=lambda scene: (counts[scene], scene))


def _size_text(df: pd.DataFrame) -> str:
    sizes = sorted(
        {(int(w), int(h)) for w, h in zip(df[names.WIDTH], df[names.HEIGHT])}, key=lambda s: (s[0] * s[1], s)
    )
    return ", ".join(f"{w}x{h}" for w, h in sizes)


def speedup_vs_threads(scaling: pd.DataFrame, stem: Path) -> list[Path]:
    """Strong scaling: speedup over the fewest threads vs threads, with the
    ideal (linear) line; one line per renderer / lanes / scene / stage."""
    if scaling.empty:
        return []
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    keys = [names.RENDERER, names.LANES, names.ACCEL, names.TRAVERSAL, names.HYBRID_THRESHOLD, *names.GPU_AXES]
    keys += [names.SCENE, names.STAGE, names.WIDTH, names.HEIGHT]
    for key, group in scaling.groupby(keys, sort=False, dropna=False):
        renderer, lanes, scene, stage = key[0], key[1], key[-4], key[-3]
        lane_text = f" l{lanes}" if lanes > 1 else ""
        accel_text = "".join(f" {tag}" for tag in names.accel_tag(group.iloc[0]))
        ax.plot(
            group[names.THREADS],
            group["scaling_speedup"],
            marker="o",
            label=f"{renderer}{lane_text}{accel_text} {scene} {stage}",
        )
    top = int(scaling[names.THREADS].max())
    ax.plot([1, top], [1, top], "k--", linewidth=1, label="ideal")
    ax.set_xlabel("threads")
    ax.set_ylabel("speedup over fewest threads (median render_ms)")
    ax.set_xticks(sorted(pd.unique(scaling[names.THREADS])))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title("Strong scaling")
    return save(fig, stem)


def _grid(frames: pd.DataFrame):
    stages_ = _ordered(frames[names.STAGE], names.stage_order)
    scenes = list(pd.unique(frames[names.SCENE]))
    fig, axes = plt.subplots(
        len(stages_), len(scenes), figsize=(4.0 * len(scenes) + 1.5, 2.8 * len(stages_) + 0.6), squeeze=False
    )
    return fig, axes, stages_, scenes


def _config_label(group: pd.DataFrame, with_size: bool = False) -> str:
    return _renderer_label(group.iloc[0], with_size)


def frame_series(frames: pd.DataFrame, stem: Path) -> list[Path]:
    """render_ms of every frame in run order (repetitions one after another),
    warm-up frames hollow, flagged outliers crossed; one panel per stage x
    scene. Shows warm-up effects, drift and spikes that a median hides."""
    if frames.empty:
        return []
    fig, axes, stages_, scenes = _grid(frames)
    outliers = stats.flag_outliers(frames)
    with_size = _several_sizes(frames)
    for (i, stage), (j, scene) in ((a, b) for a in enumerate(stages_) for b in enumerate(scenes)):
        ax = axes[i][j]
        part = frames[(frames[names.STAGE] == stage) & (frames[names.SCENE] == scene)]
        configs = part.groupby(names.CONFIG_ID, sort=False)
        colors = _palette(configs.ngroups)
        for k, (_, group) in enumerate(configs):
            group = group.sort_values([names.REPETITION, names.FRAME])
            x = np.arange(len(group))
            color = colors(k)
            warm = group[names.WARMUP].to_numpy() == 1
            y = group[names.RENDER_MS].to_numpy()
            ax.plot(x, y, color=color, linewidth=0.8, label=_config_label(group, with_size))
            # The markers, one per frame, as pixels in the SVG too: as vector
            # paths a run of a few hundred configurations drew a 2 MB file.
            ax.scatter(x[~warm], y[~warm], color=color, s=8, rasterized=True)
            ax.scatter(x[warm], y[warm], facecolors="none", edgecolors=color, s=14, rasterized=True)
            flagged = outliers.loc[group.index].to_numpy()
            ax.scatter(x[flagged], y[flagged], color="red", marker="x", s=30, zorder=3, rasterized=True)
            for boundary in np.flatnonzero(np.diff(group[names.REPETITION].to_numpy())) + 0.5:
                ax.axvline(boundary, color="grey", linestyle=":", linewidth=0.8)
        _log_y(ax, part[names.RENDER_MS])
        ax.xaxis.set_major_locator(matplotlib.ticker.MaxNLocator(integer=True))
        ax.set_title(f"{scene}, {stage}", fontsize=8)
        ax.grid(alpha=0.3, which="both")
        if len(part):
            ax.legend(fontsize=6, ncol=1 if configs.ngroups <= 10 else 2)
    fig.supxlabel("frame, repetitions in run order, dotted: next repetition (hollow: warm-up; red x: outlier)")
    fig.supylabel("render_ms (log scale)")
    return save(fig, stem)


def distributions(frames: pd.DataFrame, stem: Path) -> list[Path]:
    """Box plots of the measured frame times per configuration; one panel per
    stage x scene, log scale."""
    meas = stats.measured(frames)
    if meas.empty:
        return []
    fig, axes, stages_, scenes = _grid(meas)
    with_size = _several_sizes(meas)
    for (i, stage), (j, scene) in ((a, b) for a in enumerate(stages_) for b in enumerate(scenes)):
        ax = axes[i][j]
        part = meas[(meas[names.STAGE] == stage) & (meas[names.SCENE] == scene)]
        groups = [g for _, g in part.groupby(names.CONFIG_ID, sort=False)]
        groups.sort(key=lambda g: names.renderer_order(g[names.RENDERER].iloc[0]))
        if groups:
            ax.boxplot([g[names.RENDER_MS].to_numpy() for g in groups], showmeans=True, widths=0.6)
            ax.set_xticks(
                range(1, len(groups) + 1),
                [_config_label(g, with_size) for g in groups],
                rotation=30,
                ha="right",
                fontsize=7,
            )
        _log_y(ax, part[names.RENDER_MS])
        ax.set_title(f"{scene}, {stage}", fontsize=8)
        ax.grid(axis="y", alpha=0.3, which="both")
    fig.supylabel("render_ms of measured frames (log scale)")
    fig.suptitle("Frame-time distributions (box: quartiles, whiskers 1.5 IQR, triangle: mean)")
    return save(fig, stem)


def thesis_speedups(side: pd.DataFrame, stem: Path) -> list[Path]:
    """Speedup over the reference per renderer and stage, thesis vs ours, for
    one scene (log scale): the comparable part of the two studies."""
    if side.empty:
        return []
    side = side.astype({"thesis": float, "ours": float})
    side = side[np.isfinite(side["thesis"]) & np.isfinite(side["ours"])]
    if side.empty:
        return []
    labels = [f"{r}\n{s}" for r, s in zip(side["renderer"], side["stage"])]
    x = np.arange(len(side))
    fig, ax = plt.subplots(figsize=(max(5.0, 0.7 * len(side) + 1.5), 4.0))
    ax.bar(x - 0.2, side["thesis"], 0.4, label="thesis (M1, -O0)")
    ax.bar(x + 0.2, side["ours"], 0.4, label="ours")
    ax.axhline(1.0, color="k", linewidth=0.8)
    _log_y(ax, np.concatenate([side["thesis"].to_numpy(), side["ours"].to_numpy(), [1.0]]))
    ax.set_xticks(x, labels, fontsize=7)
    ax.set_ylabel(f"speedup over {names.reference_renderer()} (log scale)")
    ax.set_title(f"Speedups, thesis vs ours: {side['scene'].iloc[0]}")
    ax.grid(axis="y", alpha=0.3, which="both")
    ax.legend()
    return save(fig, stem)


# Markers of the accels in the cost-vs-spheres figure, in schema order.
ACCEL_MARKERS = "osD^v"


def cost_vs_spheres(curves: pd.DataFrame, fits: pd.DataFrame, stem: Path) -> list[Path]:
    """Median render_ms vs sphere count, log-log, one line per configuration
    that ran on several sphere counts (metrics.sphere_curves), its fitted
    power law dashed and its exponent k in the legend."""
    if fits.empty:
        return []
    fig, ax = plt.subplots(figsize=(8.4, 4.6))
    colors = _palette(len(fits))
    label_keys = _varying(fits, [names.STAGE, names.WIDTH, names.HEIGHT, names.BUILD_TYPE])
    for i, fit in enumerate(fits.itertuples(index=False)):
        fit = fit._asdict()
        points = curves[curves[metrics.CURVE] == fit[metrics.CURVE]]
        color = colors(i)
        marker = ACCEL_MARKERS[names.accel_order(fit[names.ACCEL]) % len(ACCEL_MARKERS)]
        label = " ".join(
            [
                fit[names.RENDERER],
                *_option_texts(fit),
                fit[names.ACCEL],
                *names.variant_tag(fit),
                *(str(fit[key]) for key in label_keys),
            ]
        )
        ax.plot(
            points[names.SPHERES],
            points["median"],
            marker=marker,
            linestyle="none",
            color=color,
            label=f"{label}: k = {fit['exponent']:.2f}",
        )
        n = np.geomspace(fit["spheres_min"], fit["spheres_max"], 32)
        ax.plot(n, fit["coefficient"] * n ** fit["exponent"], linestyle="--", linewidth=1, color=color)
    ax.set_xscale("log")
    _log_y(ax, curves["median"], pad=1.4)
    ax.set_xlabel("spheres N (log scale)")
    ax.set_ylabel("render_ms per frame (median, log scale)")
    ax.grid(alpha=0.3, which="both")
    # Beside the axes: inside, it hides the points of the cheapest lines.
    ax.legend(fontsize=7, title="dashed: fit ms = c N^k", title_fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1))
    ax.set_title(f"Cost vs spheres ({_size_text(curves)})")
    return save(fig, stem)


def _varying(df: pd.DataFrame, keys: list[str]) -> list[str]:
    """The keys whose value differs between rows: what a label must show."""
    return [key for key in keys if df[key].nunique(dropna=False) > 1]


def karp_flatt_vs_p(metrics_table: pd.DataFrame, stem: Path) -> list[Path]:
    """Karp-Flatt e against p = threads x lanes for the CPU renderers that ran
    at several p on the same work (scene, stage, accel, size): one line per
    renderer and lane width over its thread counts (a renderer without
    threads: one line over its lane widths). Flat e: the loss is serial work;
    rising e: parallel overhead grows with p. [] without such data."""
    if metrics_table.empty:
        return []
    on_cpu = metrics_table[names.RENDERER].map(names.renders_on_cpu).astype(bool)
    cpu = metrics_table[on_cpu & np.isfinite(metrics_table["karp_flatt"].astype(float))]
    work = [names.SCENE, names.STAGE, names.ACCEL, names.TRAVERSAL, names.HYBRID_THRESHOLD, *names.GPU_AXES]
    work += [names.WIDTH, names.HEIGHT, names.BUILD_TYPE]
    families = [g for _, g in cpu.groupby([names.RENDERER, *work], sort=False, dropna=False) if g["p"].nunique() > 1]
    if not families:
        return []
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    label_keys = _varying(
        pd.concat(families), [names.SCENE, names.STAGE, names.ACCEL, names.TRAVERSAL, names.WIDTH, names.BUILD_TYPE]
    )
    for family in families:
        renderer = family[names.RENDERER].iloc[0]
        by_lanes = names.accepts(renderer, names.THREADS)
        for lanes, line in family.groupby(names.LANES, sort=True) if by_lanes else [(None, family)]:
            line = line.sort_values("p")
            text = " ".join(
                [
                    renderer,
                    *([f"l{lanes}"] if lanes and lanes > 1 else []),
                    *(str(line[key].iloc[0]) for key in label_keys),
                ]
            )
            ax.plot(line["p"], line["karp_flatt"], marker="o", label=text)
    ax.set_xscale("log", base=2)
    ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    ax.set_xlabel("p = threads x lanes (log scale)")
    ax.set_ylabel("Karp-Flatt e (experimentally determined serial fraction)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    ax.set_title("Karp-Flatt metric against p")
    return save(fig, stem)
