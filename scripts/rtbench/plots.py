"""The report's figures (matplotlib, Agg backend: no display, no plt.show()).

Each function draws one figure from the summary or the tidy frames and saves
it as PNG and SVG (atomically); it returns the paths written, or [] when the
run has no data for that figure (e.g. no thread scaling in a `quick` run).
"""

from __future__ import annotations

import textwrap
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


def _suptitle(fig, text: str) -> None:
    """The figure's title, a fixed 0.06 inch below its top edge: tight_layout
    leaves the title's height free above the axes, which the default place
    (98 % of the height) overruns in a tall figure."""
    fig.suptitle(text, y=1 - 0.06 / fig.get_size_inches()[1])


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


# --- what a panel draws ----------------------------------------------------------

# A panel draws at most this many series (lines, bar groups, boxes): beyond
# about eight, colours and markers no longer tell them apart at a glance.
MAX_SERIES = 8
# The series' colours: tab10 less its red (frame_series' outlier crosses) and
# its grey; black is the peers'. One per series of a panel, so none repeats.
COLORS = [plt.get_cmap("tab10")(i) for i in (0, 1, 2, 4, 5, 6, 8, 9)]
# The markers of the accels, in schema order (brute force first).
ACCEL_MARKERS = "osD^v"
# The peers (names.PEERS) in every figure: one style, defined here only.
PEER_STYLE = {"color": "black", "linestyle": "--", "marker": "*"}
# A series' line: solid, unless it is a peer's.
LINE = "-"
# Where a figure leaves configurations out, the table that has them all.
ALL_CONFIGURATIONS = "tables/summary.md"
# The keys of a series: a renderer, its accel and the image size and build it
# ran at. Of its variants (traversal, GPU variant, threads and lanes) a figure
# draws the fastest.
SERIES_KEYS = [names.RENDERER, names.ACCEL, names.WIDTH, names.HEIGHT, names.BUILD_TYPE]
# What is not a variant: where a configuration ran (a point of its series).
POINT_KEYS = [names.SCENE, names.SPHERES, names.STAGE, names.ALGORITHM, names.EARLY_EXIT]
CPU, GPU = "CPU", "GPU"


def device_of(renderer: str) -> str:
    """The panel a renderer draws in: CPU or GPU (their times differ by orders of magnitude)."""
    return CPU if names.renders_on_cpu(renderer) else GPU


def _devices(renderers) -> list[str]:
    present = {device_of(r) for r in renderers}
    return [d for d in (CPU, GPU) if d in present]


def _key_text(df: pd.DataFrame, keys: list[str]) -> pd.Series:
    """One string per row of the keys' values (NaN as 'nan'): a groupable id."""
    return df[keys].astype(str).agg("|".join, axis=1) if len(df) else pd.Series([], dtype=str)


def _ranked(rows: pd.DataFrame, by: str, point: str) -> list[str]:
    """The values of `by`, fastest first: by the mean log median over the
    points (`point`) that all of them ran, or each over its own where they
    share none; ties keep the rows' order."""
    groups = list(rows.groupby(by, sort=False))
    shared = set.intersection(*(set(g[point]) for _, g in groups))
    scores = []
    for value, g in groups:
        on = g[g[point].isin(shared)] if shared else g
        scores.append((float(np.log(on["median"].astype(float)).mean()), value))
    return [value for _, value in sorted(scores, key=lambda s: s[0])]


def choose_series(rows: pd.DataFrame, point_keys: list[str]) -> tuple[pd.DataFrame, dict[str, dict], int]:
    """The series a figure draws, from rows of a median each (`median`) per
    configuration and point (`point_keys`: where it ran). Per series
    (SERIES_KEYS) its fastest variant; per device (CPU, GPU) the peer, then
    each renderer's fastest series, then its second, ..., at most MAX_SERIES
    (a peer only its fastest).
    Returns the chosen rows (columns _device and _series added, in schema
    order), the style of each _series (PEER_STYLE for a peer, else a colour
    of its own within the device and its accel's marker) and how many
    configurations it left out."""
    if rows.empty:
        return rows.assign(_device=[], _series=[]), {}, 0
    variant_keys = [k for k in names.CONFIG_KEYS if k in rows and k not in SERIES_KEYS + POINT_KEYS]
    rows = rows.assign(
        _device=rows[names.RENDERER].map(device_of),
        _series=_key_text(rows, SERIES_KEYS),
        _variant=_key_text(rows, variant_keys),
        _point=_key_text(rows, point_keys),
    )
    variants = rows[["_series", "_variant"]].drop_duplicates()
    best = {series: _ranked(g, "_variant", "_point")[0] for series, g in rows.groupby("_series", sort=False)}
    rows = rows[rows["_variant"] == rows["_series"].map(best)]
    kept, styles = [], {}
    for device in _devices(rows[names.RENDERER]):
        part = rows[rows["_device"] == device]
        rank = {}
        for _, g in part.groupby(names.RENDERER, sort=False):
            rank.update({series: i for i, series in enumerate(_ranked(g, "_series", "_point"))})
        first = part.drop_duplicates("_series")
        order = sorted(
            first.to_dict("records"),
            key=lambda r: (
                r[names.RENDERER] not in names.PEERS,
                rank[r["_series"]],
                names.renderer_order(r[names.RENDERER]),
            ),
        )
        # A peer draws once: PEER_STYLE tells no two of its series apart.
        order = [r for r in order if r[names.RENDERER] not in names.PEERS or rank[r["_series"]] == 0]
        chosen = {r["_series"] for r in order[:MAX_SERIES]}
        drawn = first[first["_series"].isin(chosen)]
        drawn = drawn.assign(
            _r=drawn[names.RENDERER].map(names.renderer_order), _a=drawn[names.ACCEL].map(names.accel_order)
        ).sort_values(["_r", "_a", names.WIDTH, names.HEIGHT], kind="stable")
        colour = iter(COLORS)
        for r in drawn.to_dict("records"):
            marker = ACCEL_MARKERS[names.accel_order(r[names.ACCEL]) % len(ACCEL_MARKERS)]
            peer = r[names.RENDERER] in names.PEERS
            styles[r["_series"]] = (
                dict(PEER_STYLE) if peer else {"color": next(colour), "linestyle": LINE, "marker": marker}
            )
        kept += list(drawn["_series"])
    chosen_rows = rows[rows["_series"].isin(kept)]
    chosen_rows = chosen_rows.iloc[np.argsort([kept.index(s) for s in chosen_rows["_series"]], kind="stable")]
    left_out = len(variants) - len(kept)
    return chosen_rows.drop(columns=["_variant", "_point"]), styles, left_out


def _choice_note(left_out: int, what: str = "configurations") -> str:
    """The figure's footnote: what each panel draws, and where the rest are."""
    text = (
        f"Each panel: per renderer, accel and size its fastest configuration, at most {MAX_SERIES}; "
        f"the peers ({', '.join(names.PEERS)}; one configuration each) in black."
    )
    if left_out:
        text += f" Not drawn: {left_out} more {what}, all in {ALL_CONFIGURATIONS}."
    return text


def _note(fig, text: str, above: str = "") -> None:
    """The figure's footnote, under `above` (a label of the whole figure's x
    axes): as its supxlabel, which tight_layout leaves room for."""
    # Wrapped to the figure's width: about 17 characters of 7 pt text per inch.
    text = textwrap.fill(text, max(40, int(17 * fig.get_size_inches()[0])))
    note = f"{above}\n" if above else ""
    fig.supxlabel(f"{note}{text}", fontsize=8 if above else 7, color="black" if above else "0.3")


def _indexed_style(i: int, renderer: str = "") -> dict:
    """The style of the i-th line of a figure that picks no series (scaling,
    Karp-Flatt): colour and marker both its own, PEER_STYLE for a peer."""
    if renderer in names.PEERS:
        return dict(PEER_STYLE)
    return {"color": COLORS[i % len(COLORS)], "linestyle": LINE, "marker": "osD^v<>p"[i % 8]}


def _option_texts(row) -> list[str]:
    """The threads and lanes where the row's renderer takes them: ['t8', 'l16']."""
    return [f"{option[0]}{value}" for option, value in names.label_options(row)]


def render_bars(summary: pd.DataFrame, stem: Path) -> list[Path]:
    """Median render_ms per renderer x scene, one panel per device (rows:
    CPU, GPU) and stage (columns), log scale, with the bootstrap CI of the
    median as error bars. The bars of bar_rows: per renderer, accel and size
    its fastest variant at the most threads x lanes (as in tables 1-4; the
    other thread counts and lane widths are in the scaling and Karp-Flatt
    figures), at most MAX_SERIES per panel."""
    if summary.empty:
        return []
    df = bar_rows(summary)
    styles, left_out = df.attrs["styles"], df.attrs["left_out"]
    stages_ = _ordered(df[names.STAGE], names.stage_order)
    devices = _devices(df[names.RENDERER])
    scenes = _scenes_by_size(df)
    most = max(df.groupby("_device")["_series"].nunique())
    panel = max(4.2, 0.15 * most * len(scenes), 1.1 * len(scenes))  # inches: room for every bar and scene name
    fig, axes = plt.subplots(
        len(devices),
        len(stages_),
        figsize=(panel * len(stages_) + 2.4, 3.4 * len(devices) + 0.5),
        sharey="row",
        squeeze=False,
    )
    for row, device in zip(axes, devices):
        part = df[df["_device"] == device]
        series = list(pd.unique(part["_series"]))
        width = 0.8 / len(series)
        for ax, stage in zip(row, stages_):
            here = part[part[names.STAGE] == stage]
            for i, key in enumerate(series):
                rows = here[here["_series"] == key]
                label = part.loc[part["_series"] == key, "_label"].iloc[0]
                _bars(
                    ax, rows, scenes, (i - (len(series) - 1) / 2) * width, width, label=label, **_bar_style(styles[key])
                )
            _log_y(
                ax,
                np.concatenate([part["ci_low"].to_numpy(dtype=float), part["ci_high"].to_numpy(dtype=float)]),
                pad=1.6,
            )
            ax.set_title(f"{device}, stage {stage}")
            ax.set_xticks(np.arange(len(scenes)), scenes)
            ax.grid(axis="y", which="both", alpha=0.3)
        row[0].set_ylabel(f"{device}: render_ms per frame\n(median, log scale)")
        handles = {h.get_label(): h for ax in row for h in ax.get_legend_handles_labels()[0]}
        labels = [part.loc[part["_series"] == key, "_label"].iloc[0] for key in series]
        row[-1].legend(
            [handles[label] for label in labels if label in handles],
            [label for label in labels if label in handles],
            fontsize=7,
            loc="upper left",
            bbox_to_anchor=(1.02, 1),
        )
    _suptitle(fig, f"Render time per frame ({_size_text(df)})")
    _note(fig, _choice_note(left_out))
    return save(fig, stem)


def _bar_style(style: dict) -> dict:
    """A series' line style as a bar's: its colour, a peer's bar hollow and
    hatched in PEER_STYLE's colour (a bar has no marker or dash)."""
    if style == PEER_STYLE:
        return {"facecolor": "white", "edgecolor": PEER_STYLE["color"], "hatch": "////"}
    return {"color": style["color"]}


def bar_rows(summary: pd.DataFrame) -> pd.DataFrame:
    """The configurations render_bars draws, with their legend label in
    `_label`: per scene, renderer, stage, accel and size the one with the
    most threads x lanes, then choose_series' choice of them. Their styles
    are in attrs["styles"], the count of the others in attrs["left_out"]."""
    widest = tables.widest_rows(summary)
    chosen, styles, left_out = choose_series(widest, [names.STAGE, names.SCENE])
    out = chosen.assign(_label=chosen.apply(_renderer_label, axis=1, with_size=_several_sizes(widest)))
    out.attrs.update(styles=styles, left_out=left_out)
    return out


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
    lines = list(scaling.groupby(keys, sort=False, dropna=False))
    for i, (key, group) in enumerate(lines[:MAX_SERIES]):
        renderer, lanes, scene, stage = key[0], key[1], key[-4], key[-3]
        lane_text = f" l{lanes}" if lanes > 1 else ""
        accel_text = "".join(f" {tag}" for tag in names.accel_tag(group.iloc[0]))
        ax.plot(
            group[names.THREADS],
            group["scaling_speedup"],
            **_indexed_style(i, renderer),
            label=f"{renderer}{lane_text}{accel_text} {scene} {stage}",
        )
    if len(lines) > MAX_SERIES:
        _note(fig, f"Not drawn: {len(lines) - MAX_SERIES} more lines; every speedup is in tables/metrics.md.")
    top = int(scaling[names.THREADS].max())
    ax.plot([1, top], [1, top], color="0.5", linestyle=":", linewidth=1, label="ideal")
    ax.set_xlabel("threads")
    ax.set_ylabel("speedup over fewest threads (median render_ms)")
    ax.set_xticks(sorted(pd.unique(scaling[names.THREADS])))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title("Strong scaling")
    return save(fig, stem)


def _grid(frames: pd.DataFrame):
    """A row per stage and device that ran in it, a column per scene."""
    stages_ = _ordered(frames[names.STAGE], names.stage_order)
    rows = [
        (stage, device)
        for stage in stages_
        for device in _devices(frames.loc[frames[names.STAGE] == stage, names.RENDERER])
    ]
    scenes = list(pd.unique(frames[names.SCENE]))
    fig, axes = plt.subplots(
        len(rows), len(scenes), figsize=(4.4 * len(scenes) + 1.5, 2.9 * len(rows) + 0.8), squeeze=False
    )
    return fig, axes, rows, scenes


def frame_choice(frames: pd.DataFrame) -> tuple[pd.DataFrame, dict[str, dict], int]:
    """The frames of the configurations frame_series and distributions draw:
    those render_bars draws (bar_rows: the most threads x lanes, then
    choose_series), chosen by the median of their measured frames; with
    choose_series' styles and count of the others."""
    meas = stats.measured(frames)
    if meas.empty:
        return frames.iloc[0:0].assign(_device=[], _series=[]), {}, 0
    configs = meas.groupby(names.CONFIG_ID, sort=False)
    per_config = configs.first().assign(median=configs[names.RENDER_MS].median()).reset_index()
    chosen, styles, left_out = choose_series(tables.widest_rows(per_config), [names.STAGE, names.SCENE])
    keep = chosen[[names.CONFIG_ID, "_device", "_series"]]
    order = {config: i for i, config in enumerate(keep[names.CONFIG_ID])}
    # `_frame_index`: the frame's row in `frames`, where stats.flag_outliers has its flag.
    out = frames.assign(_frame_index=frames.index).merge(keep, on=names.CONFIG_ID, how="inner", sort=False)
    out = out.iloc[np.argsort(out[names.CONFIG_ID].map(order).to_numpy(), kind="stable")]
    return out, styles, left_out


def _config_label(group: pd.DataFrame, with_size: bool = False) -> str:
    return _renderer_label(group.iloc[0], with_size)


def frame_series(frames: pd.DataFrame, stem: Path) -> list[Path]:
    """render_ms of every frame in run order (repetitions one after another),
    warm-up frames hollow, flagged outliers crossed; one panel per stage x
    device x scene, the configurations of frame_choice. Shows warm-up
    effects, drift and spikes that a median hides."""
    if frames.empty:
        return []
    outliers = stats.flag_outliers(frames)
    drawn, styles, left_out = frame_choice(frames)
    if drawn.empty:
        return []
    fig, axes, rows, scenes = _grid(drawn)
    with_size = _several_sizes(frames)
    for (i, (stage, device)), (j, scene) in ((a, b) for a in enumerate(rows) for b in enumerate(scenes)):
        ax = axes[i][j]
        part = drawn[(drawn[names.STAGE] == stage) & (drawn[names.SCENE] == scene) & (drawn["_device"] == device)]
        for _, group in part.groupby(names.CONFIG_ID, sort=False):
            group = group.sort_values([names.REPETITION, names.FRAME])
            style = styles[group["_series"].iloc[0]]
            color, marker = style["color"], style["marker"]
            x = np.arange(len(group))
            warm = group[names.WARMUP].to_numpy() == 1
            y = group[names.RENDER_MS].to_numpy()
            ax.plot(
                x, y, color=color, linestyle=style["linestyle"], linewidth=0.8, label=_config_label(group, with_size)
            )
            # The markers, one per frame, as pixels in the SVG too: as vector
            # paths a run of a few hundred configurations drew a 2 MB file.
            ax.scatter(x[~warm], y[~warm], color=color, marker=marker, s=8, rasterized=True)
            ax.scatter(x[warm], y[warm], facecolors="none", edgecolors=color, marker=marker, s=14, rasterized=True)
            flagged = outliers.loc[group["_frame_index"]].to_numpy()
            ax.scatter(x[flagged], y[flagged], color="red", marker="x", s=30, zorder=3, rasterized=True)
            for boundary in np.flatnonzero(np.diff(group[names.REPETITION].to_numpy())) + 0.5:
                ax.axvline(boundary, color="grey", linestyle=":", linewidth=0.8)
        _log_y(ax, part[names.RENDER_MS])
        ax.xaxis.set_major_locator(matplotlib.ticker.MaxNLocator(integer=True))
        ax.set_title(f"{device}: {scene}, {stage}", fontsize=8)
        ax.grid(alpha=0.3, which="both")
        if len(part):
            ax.legend(fontsize=6)
    fig.supylabel("render_ms (log scale)")
    _note(
        fig,
        _choice_note(left_out),
        "frame, repetitions in run order, dotted: next repetition (hollow: warm-up; red x: outlier)",
    )
    return save(fig, stem)


def distributions(frames: pd.DataFrame, stem: Path) -> list[Path]:
    """Box plots of the measured frame times per configuration; one panel per
    stage x device x scene, the configurations of frame_choice, log scale."""
    meas = stats.measured(frames)
    if meas.empty:
        return []
    drawn, styles, left_out = frame_choice(meas)
    fig, axes, rows, scenes = _grid(drawn)
    with_size = _several_sizes(meas)
    for (i, (stage, device)), (j, scene) in ((a, b) for a in enumerate(rows) for b in enumerate(scenes)):
        ax = axes[i][j]
        part = drawn[(drawn[names.STAGE] == stage) & (drawn[names.SCENE] == scene) & (drawn["_device"] == device)]
        groups = [g for _, g in part.groupby(names.CONFIG_ID, sort=False)]
        if groups:
            boxes = ax.boxplot(
                [g[names.RENDER_MS].to_numpy() for g in groups],
                showmeans=True,
                widths=0.6,
                patch_artist=True,
                medianprops={"color": "black"},
                meanprops={"markerfacecolor": "white", "markeredgecolor": "black"},
            )
            for k, g in enumerate(groups):
                style = styles[g["_series"].iloc[0]]
                peer = style == PEER_STYLE
                box = boxes["boxes"][k]
                box.set_facecolor("white" if peer else (*style["color"][:3], 0.35))
                box.set_edgecolor(style["color"])
                box.set_linestyle(style["linestyle"])
                if peer:
                    box.set_hatch("////")
            ax.set_xticks(
                range(1, len(groups) + 1),
                [_config_label(g, with_size) for g in groups],
                rotation=30,
                ha="right",
                fontsize=7,
            )
        _log_y(ax, part[names.RENDER_MS])
        ax.set_title(f"{device}: {scene}, {stage}", fontsize=8)
        ax.grid(axis="y", alpha=0.3, which="both")
    fig.supylabel("render_ms of measured frames (log scale)")
    _suptitle(fig, "Frame-time distributions (box: quartiles, line: median, whiskers 1.5 IQR, triangle: mean)")
    _note(fig, _choice_note(left_out))
    return save(fig, stem)


def thesis_speedups(side: pd.DataFrame, stem: Path) -> list[Path]:
    """Speedup over the reference per renderer and stage, thesis vs ours, for
    one scene (log scale), the CPU and the GPU renderers in panels of their
    own: the comparable part of the two studies."""
    if side.empty:
        return []
    side = side.astype({"thesis": float, "ours": float})
    side = side[np.isfinite(side["thesis"]) & np.isfinite(side["ours"])]
    if side.empty:
        return []
    side = side.assign(_device=side["renderer"].map(device_of))
    devices = _devices(side["renderer"])
    counts = [int((side["_device"] == d).sum()) for d in devices]
    fig, axes = plt.subplots(
        1,
        len(devices),
        figsize=(max(5.0, 0.7 * len(side) + 0.8 * len(devices) + 1.5), 4.0),
        sharey=True,
        squeeze=False,
        gridspec_kw={"width_ratios": counts},
    )
    every = np.concatenate([side["thesis"].to_numpy(), side["ours"].to_numpy(), [1.0]])
    for ax, device in zip(axes[0], devices):
        part = side[side["_device"] == device]
        labels = [f"{r}\n{s}" for r, s in zip(part["renderer"], part["stage"])]
        x = np.arange(len(part))
        ax.bar(x - 0.2, part["thesis"], 0.4, label="thesis (M1, -O0)", color=COLORS[0])
        ax.bar(x + 0.2, part["ours"], 0.4, label="ours", color=COLORS[1])
        ax.axhline(1.0, color="k", linewidth=0.8)
        _log_y(ax, every)
        ax.set_xticks(x, labels, fontsize=7)
        ax.set_title(device)
        ax.grid(axis="y", alpha=0.3, which="both")
    axes[0][0].set_ylabel(f"speedup over {names.reference_renderer()} (log scale)")
    axes[0][0].legend()
    _suptitle(fig, f"Speedups, thesis vs ours: {side['scene'].iloc[0]}")
    return save(fig, stem)


def cost_vs_spheres(curves: pd.DataFrame, fits: pd.DataFrame, stem: Path) -> list[Path]:
    """Median render_ms vs sphere count, log-log, one panel per device (rows:
    CPU, GPU) and stage (columns): a line per series of choose_series that
    ran on several sphere counts (metrics.sphere_curves), its fitted power
    law as a line and its exponent k in the legend. Every fit is in the
    cost-vs-spheres table."""
    if fits.empty:
        return []
    chosen, styles, left_out = choose_series(curves, [names.STAGE, names.SPHERES])
    stages_ = _ordered(chosen[names.STAGE], names.stage_order)
    devices = _devices(chosen[names.RENDERER])
    fig, axes = plt.subplots(
        len(devices), len(stages_), figsize=(4.6 * len(stages_) + 0.4, 5.6 * len(devices) + 0.4), squeeze=False
    )
    fit_of = fits.set_index(metrics.CURVE)
    with_size = _several_sizes(fits)
    label_keys = _varying(fits, [names.BUILD_TYPE])
    for row, device in zip(axes, devices):
        for ax, stage in zip(row, stages_):
            part = chosen[(chosen["_device"] == device) & (chosen[names.STAGE] == stage)]
            for curve, points in part.groupby(metrics.CURVE, sort=False):
                fit = {metrics.CURVE: curve, **fit_of.loc[curve].to_dict()}
                style = styles[points["_series"].iloc[0]]
                label = " ".join(
                    [
                        fit[names.RENDERER],
                        *_option_texts(fit),
                        fit[names.ACCEL],
                        *names.variant_tag(fit),
                        *([f"{fit[names.WIDTH]}x{fit[names.HEIGHT]}"] if with_size else []),
                        *(str(fit[key]) for key in label_keys),
                    ]
                )
                ax.plot(
                    points[names.SPHERES],
                    points["median"],
                    marker=style["marker"],
                    linestyle="none",
                    color=style["color"],
                    label=f"{label}: k = {fit['exponent']:.2f}",
                )
                n = np.geomspace(fit["spheres_min"], fit["spheres_max"], 32)
                ax.plot(
                    n,
                    fit["coefficient"] * n ** fit["exponent"],
                    linestyle=style["linestyle"],
                    linewidth=1,
                    color=style["color"],
                )
            ax.set_xscale("log")
            _log_y(ax, chosen.loc[chosen["_device"] == device, "median"], pad=1.4)
            ax.set_xlabel("spheres N (log scale)")
            ax.set_title(f"{device}, stage {stage}")
            ax.grid(alpha=0.3, which="both")
            # Below the axes: inside, it hides the points of the cheapest lines.
            if len(part):
                ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16))
        row[0].set_ylabel(f"{device}: render_ms per frame\n(median, log scale)")
    _suptitle(fig, f"Cost vs spheres ({_size_text(curves)}); lines: fit ms = c N^k")
    _note(fig, _choice_note(left_out) + " Every fit: tables/cost-vs-spheres.md.")
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
    lines = []
    for family in families:
        renderer = family[names.RENDERER].iloc[0]
        by_lanes = names.accepts(renderer, names.THREADS)
        for lanes, line in family.groupby(names.LANES, sort=True) if by_lanes else [(None, family)]:
            lines.append((renderer, lanes, line.sort_values("p")))
    for i, (renderer, lanes, line) in enumerate(lines[:MAX_SERIES]):
        text = " ".join(
            [
                renderer,
                *([f"l{lanes}"] if lanes and lanes > 1 else []),
                *(str(line[key].iloc[0]) for key in label_keys),
            ]
        )
        ax.plot(line["p"], line["karp_flatt"], **_indexed_style(i, renderer), label=text)
    if len(lines) > MAX_SERIES:
        _note(fig, f"Not drawn: {len(lines) - MAX_SERIES} more lines; every e is in tables/metrics.md.")
    ax.set_xscale("log", base=2)
    ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    ax.set_xlabel("p = threads x lanes (log scale)")
    ax.set_ylabel("Karp-Flatt e (experimentally determined serial fraction)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    ax.set_title("Karp-Flatt metric against p")
    return save(fig, stem)
