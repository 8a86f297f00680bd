"""Run directories -> one tidy pandas DataFrame (one row per frame).

Every CSV is checked strictly against the schema before it is used: a file
that is truncated, corrupted or does not match its metadata sidecar stops
the report with an error naming the file (and the line), instead of quietly
becoming a wrong median.

Layout written by the bench runner (scripts/bench):

    RUN_DIR/manifest.json                  configurations, runs, status
    RUN_DIR/frames/<config>-r<rep>.csv     the raytracer's per-frame CSV
    RUN_DIR/frames/<config>-r<rep>.meta.json   its metadata sidecar

A directory without a manifest (CSVs written by hand with --csv) loads too:
every *.csv below it with its .meta.json beside it.
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import pandas as pd

from rtbench import emulation, names
from rtbench.run_status import NOT_RUN, RunStatus

MANIFEST = "manifest.json"
FRAMES_DIR = "frames"
META_SUFFIX = ".meta.json"


class RunDataError(ValueError):
    """Input that cannot be trusted; the message starts with the file's path."""


def meta_path_for(csv_path: Path) -> Path:
    """The sidecar the raytracer writes by default: FILE.csv -> FILE.meta.json."""
    return csv_path.with_name(csv_path.stem + META_SUFFIX)


# --- one file ------------------------------------------------------------------


def read_frame_csv(path: Path) -> dict[str, list]:
    """Reads a frame CSV into columns, converting each by its schema type. A
    CSV written before some of the schema's optional columns (names.OPTIONAL_COLUMNS)
    reads as if they were empty: no traversal, no GPU variants, no counters."""
    try:
        with path.open(newline="", encoding="utf-8") as f:
            rows = list(csv.reader(f))
    except (OSError, UnicodeDecodeError, csv.Error) as e:
        raise RunDataError(f"{path}: cannot read: {e}") from None
    if not rows:
        raise RunDataError(f"{path}: empty file (no header, no frames)")
    header = rows[0]
    _check_header(path, header)
    if len(rows) == 1:
        raise RunDataError(f"{path}: header only, no frames (truncated?)")
    columns: dict[str, list] = {c: [] for c in names.CSV_COLUMNS}
    for lineno, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise RunDataError(
                f"{path}: line {lineno}: {len(row)} fields, expected {len(header)} (truncated or corrupted?)"
            )
        for column, text in zip(header, row):
            columns[column].append(_convert(path, lineno, column, text))
    for column in names.CSV_COLUMNS:
        if column not in header:
            columns[column] = [_convert(path, 0, column, "")] * (len(rows) - 1)
    _check_values(path, columns)
    return columns


def _check_header(path: Path, header: list[str]) -> None:
    """The schema's columns in its order; only optional ones may be missing (an older CSV)."""
    if header == [c for c in names.CSV_COLUMNS if c in header or c not in names.OPTIONAL_COLUMNS]:
        return
    missing = [c for c in names.CSV_COLUMNS if c not in header and c not in names.OPTIONAL_COLUMNS]
    extra = [c for c in header if c not in names.CSV_COLUMNS]
    detail = []
    if missing:
        detail.append(f"missing {', '.join(missing)}")
    if extra:
        detail.append(f"unexpected {', '.join(extra)}")
    if not detail:
        detail.append("columns out of order or repeated")
    raise RunDataError(f"{path}: header does not match the schema's frame_csv ({'; '.join(detail)})")


def _convert(path: Path, lineno: int, column: str, text: str):
    kind = names.COLUMN_TYPES[column]
    try:
        if kind == "int":
            if text == "" and column in names.OPTIONAL_COLUMNS:
                return None
            return int(text)
        if kind == "float":
            if text == "":
                return math.nan
            value = float(text)
            if not math.isfinite(value):
                raise ValueError
            return value
    except ValueError:
        raise RunDataError(f"{path}: line {lineno}: column {column}: {text!r} is not a valid {kind}") from None
    return text


def _check_values(path: Path, columns: dict[str, list]) -> None:
    """Values the schema constrains: names, flags, frame numbering, and float
    columns that are either measured in every frame or in none."""
    _check_members(path, names.RENDERER, columns[names.RENDERER], names.RENDERERS)
    _check_members(path, names.ALGORITHM, columns[names.ALGORITHM], names.ALGORITHMS)
    _check_members(path, names.ACCEL, columns[names.ACCEL], names.RUN_ACCELS)
    _check_members(path, names.PRECISION, columns[names.PRECISION], ["", *names.PRECISIONS])
    for text in set(columns[names.EARLY_EXIT]):
        bad = names.parse_early_exits(text) - set(names.EARLY_EXITS)
        if bad:
            raise RunDataError(f"{path}: column {names.EARLY_EXIT}: unknown early exit {sorted(bad)[0]!r}")
    _check_members(path, names.WARMUP, columns[names.WARMUP], [0, 1])
    if len(set(columns[names.RUN_ID])) != 1:
        raise RunDataError(f"{path}: more than one {names.RUN_ID} in one file")
    if columns[names.FRAME] != list(range(len(columns[names.FRAME]))):
        raise RunDataError(f"{path}: frames are not numbered 0..{len(columns[names.FRAME]) - 1} (rows lost?)")
    for column, kind in names.COLUMN_TYPES.items():
        if kind == "float" or column in names.COUNTER_COLUMNS:
            empty = sum(_empty(v) for v in columns[column])
            if 0 < empty < len(columns[column]):
                raise RunDataError(f"{path}: column {column} is empty in {empty} of {len(columns[column])} frames")
    _check_traversals(path, columns)
    _check_gpu_axes(path, columns)
    _check_counters(path, columns)


def _empty(value) -> bool:
    return value is None or value == "" or (isinstance(value, float) and math.isnan(value))


def _check_traversals(path: Path, columns: dict[str, list]) -> None:
    """A traversal of the schema (or none), and a hybrid threshold with traversal hybrid only."""
    _check_members(path, names.TRAVERSAL, columns[names.TRAVERSAL], ["", *names.TRAVERSALS])
    for traversal, threshold in zip(columns[names.TRAVERSAL], columns[names.HYBRID_THRESHOLD]):
        if threshold is not None and (traversal != names.HYBRID or threshold < 0):
            raise RunDataError(
                f"{path}: column {names.HYBRID_THRESHOLD}: {threshold} with traversal {traversal or '(none)'} "
                f"(a count of lanes >= 0, with traversal {names.HYBRID} only)"
            )


def _check_gpu_axes(path: Path, columns: dict[str, list]) -> None:
    """A GPU variant of the schema (or none), and only where the configuration
    has that axis (names.gpu_axes_of: the GPU renderer, its BVH with accel
    bvh only; gpu_rt's reorder); a CSV may leave an axis empty where it has
    it (written before the axis: the loader fills in the default)."""
    for axis, (members, _) in names.GPU_AXIS_VALUES.items():
        _check_members(path, axis, columns[axis], ["", *members])
        where = names.where_axis_applies(axis)
        for lineno, (value, renderer, accel) in enumerate(
            zip(columns[axis], columns[names.RENDERER], columns[names.ACCEL]), start=2
        ):
            if value and axis not in names.gpu_axes_of(renderer, accel):
                raise RunDataError(
                    f"{path}: line {lineno}: column {axis}: {value} with renderer {renderer}, accel {accel} "
                    f"(applies to {where} only)"
                )
    _check_retired_gpu_axes(path, columns)


def _check_retired_gpu_axes(path: Path, columns: dict[str, list]) -> None:
    """The retired GPU axes' columns (names.RETIRED_GPU_AXES): the value left
    or a retired one (whose run the loader leaves out: load_kept_runs), or
    none, on the gpu renderer's rows only."""
    for column, (kept, retired) in names.RETIRED_GPU_AXES.items():
        _check_members(path, column, columns[column], ["", kept, *retired])
        for lineno, (value, renderer) in enumerate(zip(columns[column], columns[names.RENDERER]), start=2):
            if value and renderer != names.GPU_RENDERER:
                raise RunDataError(
                    f"{path}: line {lineno}: column {column}: {value} with renderer {renderer} "
                    f"(applies to the {names.GPU_RENDERER} renderer only)"
                )


def _check_counters(path: Path, columns: dict[str, list]) -> None:
    """Counts are never negative, a kind of lane work never has more active
    lanes than slots, and rays_per_depth is counts joined by '/' that add up to rays."""
    for column in names.COUNTER_COLUMNS:
        if names.COLUMN_TYPES[column] == "int" and any(v is not None and v < 0 for v in columns[column]):
            raise RunDataError(f"{path}: column {column}: a negative count")
    for slots, active in names.LANE_WORK.values():
        for lineno, (s, a) in enumerate(zip(columns[slots], columns[active]), start=2):
            if s is not None and a is not None and a > s:
                raise RunDataError(f"{path}: line {lineno}: {active} {a} exceeds {slots} {s}")
    for lineno, (text, rays) in enumerate(zip(columns[names.RAYS_PER_DEPTH], columns[names.RAYS]), start=2):
        if text == "":
            continue
        parts = text.split(names.DEPTH_SEPARATOR)
        if not all(p.isdigit() for p in parts):
            raise RunDataError(
                f"{path}: line {lineno}: column {names.RAYS_PER_DEPTH}: {text!r} is not counts joined by "
                f"'{names.DEPTH_SEPARATOR}'"
            )
        if rays is not None and sum(map(int, parts)) != rays:
            raise RunDataError(
                f"{path}: line {lineno}: column {names.RAYS_PER_DEPTH}: {text!r} adds up to "
                f"{sum(map(int, parts))}, not {names.RAYS} {rays}"
            )


def _check_members(path: Path, column: str, values: list, allowed: list) -> None:
    bad = sorted({v for v in values if v not in allowed}, key=str)
    if bad:
        raise RunDataError(f"{path}: column {column}: unknown value {bad[0]!r} (expected one of {allowed})")


def read_metadata(path: Path) -> dict:
    """The metadata sidecar as a dict, with an error naming the file."""
    try:
        meta = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise RunDataError(f"{path}: metadata sidecar missing") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
        raise RunDataError(f"{path}: not valid JSON: {e}") from None
    if not isinstance(meta, dict) or not isinstance(meta.get(names.META_CONFIG), dict):
        raise RunDataError(f"{path}: no '{names.META_CONFIG}' object")
    return meta


def load_one(csv_path: Path, meta_path: Path, config_id: str, repetition: int, source: str) -> pd.DataFrame:
    """One run: its frames, checked against its sidecar, with the metadata
    columns the statistics group by. The device is the CSV's own column."""
    columns = read_frame_csv(csv_path)
    meta = read_metadata(meta_path)
    if reason := emulation.emulated_run_reason(meta_path, meta):
        raise RunDataError(reason)
    _check_against_meta(csv_path, meta_path, columns, meta)
    frames = pd.DataFrame(columns)
    for column in names.OPTIONAL_COLUMNS:
        if names.COLUMN_TYPES[column] == "int":
            frames[column] = pd.array(columns[column], dtype="Int64")
    frames[names.TRAVERSAL] = _traversals(frames)
    for axis in names.GPU_AXES:
        frames[axis] = _gpu_axis(frames, axis)
    for column, (kept, _) in names.RETIRED_GPU_AXES.items():
        frames[column] = [
            v or (kept if r == names.GPU_RENDERER else "") for v, r in zip(frames[column], frames[names.RENDERER])
        ]
    frames[names.PRECISION] = [names.precision_of(p) for p in frames[names.PRECISION]]
    for column, value in _agreement(meta_path, meta).items():
        frames[column] = value
    build = meta.get(names.META_BUILD) or {}
    host = meta.get(names.META_HOST) or {}
    frames[names.STAGE] = [names.stage_of(a, e) for a, e in zip(frames[names.ALGORITHM], frames[names.EARLY_EXIT])]
    frames[names.SPHERES] = _sphere_count(meta_path, meta)
    for column, value in _startup_times(meta).items():
        frames[column] = value
    frames[names.REPETITION] = repetition
    frames[names.CONFIG_ID] = config_id
    frames[names.BUILD_TYPE] = str(build.get(names.BUILD_TYPE, ""))
    # The -O level behind build_type, which the thesis' findings name where ours differ (findings.py).
    frames[names.META_BUILD_COMPILER_FLAGS] = str(build.get(names.META_BUILD_COMPILER_FLAGS) or "")
    frames[names.CPU_MODEL] = str(host.get(names.CPU_MODEL, ""))
    frames[names.LOGICAL_CORES] = int(host.get(names.LOGICAL_CORES) or 0)
    frames[names.GIT_COMMIT] = str(build.get(names.GIT_COMMIT, ""))
    frames[names.GIT_DIRTY] = bool(build.get(names.GIT_DIRTY, False))
    frames[names.SOURCE] = source
    return frames


def _traversals(frames: pd.DataFrame) -> list[str]:
    """The traversal column; where a CSV leaves it empty (or lacks it) for the
    SIMD kernel on the BVH, packets: the only traversal before the traversal
    axis (schema: traversals), so runs before and after it compare."""
    return [
        t or (names.PACKET if names.takes_traversal(r, a) else "")
        for t, r, a in zip(frames[names.TRAVERSAL], frames[names.RENDERER], frames[names.ACCEL])
    ]


def _gpu_axis(frames: pd.DataFrame, axis: str) -> list[str]:
    """One GPU axis' column; where a CSV leaves it empty (or lacks it) for a
    configuration that has the axis (names.gpu_axes_of), its default: the
    only variant before the GPU axes (binary BVH; gpu_rt: no reorder), so
    runs before and after them compare."""
    default = names.GPU_AXIS_VALUES[axis][1]
    return [
        v or (default if axis in names.gpu_axes_of(r, a) else "")
        for v, r, a in zip(frames[axis], frames[names.RENDERER], frames[names.ACCEL])
    ]


def _agreement(meta_path: Path, meta: dict) -> dict[str, float]:
    """The run's agreement with the double-precision reference (the metadata's
    agreement object, written with --agreement): NaN in every column where
    the run has none, a PSNR of null as infinity (identical images)."""
    agreement = meta.get(names.META_AGREEMENT)
    if agreement is None:
        return {column: math.nan for column in names.AGREEMENT_COLUMNS}
    if not isinstance(agreement, dict):
        raise RunDataError(f"{meta_path}: {names.META_AGREEMENT} must be an object or null, not {agreement!r}")
    values = {}
    for column in names.AGREEMENT_COLUMNS:
        value = agreement.get(column)
        if value is None and column == names.PSNR_DB:
            value = math.inf
        if not isinstance(value, (int, float)) or isinstance(value, bool):
            raise RunDataError(f"{meta_path}: {names.META_AGREEMENT}.{column} must be a number, not {value!r}")
        values[column] = float(value)
    return values


def _sphere_count(meta_path: Path, meta: dict) -> int:
    """The scene's sphere count from the metadata (0 where a sidecar lacks it)."""
    count = (meta.get(names.META_SCENE) or {}).get(names.META_SCENE_SPHERES, 0)
    if not isinstance(count, int) or isinstance(count, bool) or count < 0:
        raise RunDataError(
            f"{meta_path}: {names.META_SCENE}.{names.META_SCENE_SPHERES} must be a sphere count, not {count!r}"
        )
    return count


def _startup_times(meta: dict) -> dict[str, float]:
    """The run's load, build and prepare times in ms; NaN where the sidecar
    has none (a run from before they were recorded, or no BVH to build)."""

    def ms(value) -> float:
        ok = isinstance(value, (int, float)) and not isinstance(value, bool)
        return float(value) if ok else math.nan

    scene = meta.get(names.META_SCENE) or {}
    structure = meta.get(names.META_ACCEL_STRUCTURE) or {}
    return {
        names.LOAD_MS: ms(scene.get(names.META_SCENE_LOAD_MS)),
        names.BUILD_MS: ms(structure.get(names.META_ACCEL_BUILD_MS)),
        names.PREPARE_MS: ms(meta.get(names.META_PREPARE_MS)),
    }


def _check_against_meta(csv_path: Path, meta_path: Path, columns: dict, meta: dict) -> None:
    run_id = columns[names.RUN_ID][0]
    if meta.get(names.META_RUN_ID) != run_id:
        raise RunDataError(
            f"{csv_path}: run_id {run_id} differs from its metadata {meta_path} ({meta.get(names.META_RUN_ID)})"
        )
    config = meta[names.META_CONFIG]
    warmup, measured = names.META_CONFIG_WARMUP_FRAMES, names.META_CONFIG_MEASURED_FRAMES
    expected = config.get(warmup, 0) + config.get(measured, 0)
    if expected and expected != len(columns[names.FRAME]):
        raise RunDataError(
            f"{csv_path}: {len(columns[names.FRAME])} frames, but {meta_path} says "
            f"{config.get(warmup)} warm-up + {config.get(measured)} measured (truncated?)"
        )


# --- run directories -------------------------------------------------------------


def read_manifest(run_dir: Path) -> dict | None:
    """The runner's manifest, None when the directory has none."""
    path = run_dir / MANIFEST
    if not path.is_file():
        return None
    try:
        manifest = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, json.JSONDecodeError) as e:
        raise RunDataError(f"{path}: not valid JSON: {e}") from None
    if not isinstance(manifest.get("runs"), list):
        raise RunDataError(f"{path}: no 'runs' list")
    return manifest


def missing_runs(manifest: dict) -> dict[str, list[int]]:
    """Configuration id -> the repetitions an unfinished run has not run yet
    (pending, or interrupted while running); empty for a complete run.
    Failed and unavailable runs ran, and are not missing."""
    missing: dict[str, list[int]] = {}
    for r in manifest.get("runs", []):
        if r.get("status") in NOT_RUN:
            missing.setdefault(str(r.get("config")), []).append(int(r.get("repetition", -1)))
    return missing


def unfinished_note(run_dir: Path, manifest: dict | None) -> str | None:
    """One line on a run directory that did not finish: which configurations
    have no data at all, which lack repetitions, and how to finish it."""
    missing = missing_runs(manifest or {})
    if not missing:
        return None
    finished: dict[str, int] = {}
    for r in manifest.get("runs", []):
        if r.get("status") == RunStatus.OK:
            finished[r["config"]] = finished.get(r["config"], 0) + 1
    empty = [c for c in missing if not finished.get(c)]
    partial = [
        f"{c} ({finished[c]} of {finished[c] + len(missing[c])} repetitions)" for c in missing if finished.get(c)
    ]
    status = manifest.get("status", "?")
    if manifest.get("interrupted_by"):
        status += f" by {manifest['interrupted_by']}"
    parts = [f"run {run_dir.name} is unfinished ({status}): {sum(map(len, missing.values()))} runs missing"]
    if empty:
        parts.append(f"{len(empty)} configuration(s) have no data: {', '.join(empty)}")
    if partial:
        parts.append(f"{len(partial)} lack repetitions: {', '.join(partial)}")
    return "; ".join(parts) + f". The report covers the finished runs; finish with: scripts/bench --resume {run_dir}"


def run_entries(run_dir: Path) -> list[tuple[Path, Path, str, int]]:
    """(csv, meta, config id, repetition) of every finished run in a directory."""
    manifest = read_manifest(run_dir)
    if manifest is not None:
        return [
            (run_dir / r["csv"], run_dir / r["meta"], r["config"], int(r["repetition"]))
            for r in manifest["runs"]
            if r.get("status") == RunStatus.OK
        ]
    entries = []
    for csv_path in sorted(run_dir.rglob("*.csv")):
        entries.append((csv_path, meta_path_for(csv_path), csv_path.stem, -1))
    return entries


def load_runs(run_dirs: list[Path]) -> pd.DataFrame:
    """All finished runs of the given directories as one tidy frame, less
    those of retired GPU variants (load_kept_runs)."""
    return load_kept_runs(run_dirs)[0]


def load_kept_runs(run_dirs: list[Path]) -> tuple[pd.DataFrame, str | None]:
    """All finished runs of the given directories as one tidy frame, and a
    line on the runs left out because they ran a retired GPU variant
    (names.RETIRED_GPU_AXES: their code is gone, their measurements are in
    the record the schema names), None where there were none."""
    parts = []
    for run_dir in map(Path, run_dirs):
        if not run_dir.is_dir():
            raise RunDataError(f"{run_dir}: not a directory")
        for csv_path, meta_path, config_id, rep in run_entries(run_dir):
            source = f"{run_dir.name}/{csv_path.relative_to(run_dir)}"
            parts.append(load_one(csv_path, meta_path, config_id, rep, source))
    if not parts:
        raise RunDataError(f"{', '.join(map(str, run_dirs))}: no finished runs (no CSV with status ok)")
    kept = [p for p in parts if not _ran_retired_variant(p)]
    note = _retired_note([p for p in parts if _ran_retired_variant(p)])
    if not kept:
        raise RunDataError(f"{', '.join(map(str, run_dirs))}: nothing left to report: {note}")
    return _number_repetitions(pd.concat(kept, ignore_index=True)), note


def _ran_retired_variant(run: pd.DataFrame) -> bool:
    return any(run[column].isin(retired).any() for column, (_, retired) in names.RETIRED_GPU_AXES.items())


def _retired_note(left_out: list[pd.DataFrame]) -> str | None:
    """One line on the runs of retired GPU variants left out, None for none."""
    if not left_out:
        return None
    configs = {p[names.CONFIG_ID].iloc[0] for p in left_out}
    values = [
        f"{column} {value}"
        for column, (_, retired) in names.RETIRED_GPU_AXES.items()
        for value in retired
        if any(p[column].eq(value).any() for p in left_out)
    ]
    return (
        f"{len(left_out)} run(s) of {len(configs)} configuration(s) left out: they ran retired GPU variants "
        f"({', '.join(values)}), whose code is gone since they never gave the fastest frame; their measurements "
        f"and the commit with their code are in {', '.join(names.RETIRED_GPU_RECORDS)}"
    )


def _number_repetitions(frames: pd.DataFrame) -> pd.DataFrame:
    """Runs without a manifest (repetition -1), and runs of one configuration
    from several directories (whose repetition numbers collide), are
    renumbered 0, 1, ... in the order of their run ids, which start with the
    UTC start time. The manifest's numbering is kept otherwise."""
    runs = frames.drop_duplicates(names.RUN_ID)[[*names.CONFIG_KEYS, names.REPETITION, names.RUN_ID]]
    if (runs[names.REPETITION] >= 0).all() and not runs.duplicated([*names.CONFIG_KEYS, names.REPETITION]).any():
        return frames
    runs = runs.sort_values(names.RUN_ID)
    runs[names.REPETITION] = runs.groupby(names.CONFIG_KEYS, sort=False, dropna=False).cumcount()
    numbering = dict(zip(runs[names.RUN_ID], runs[names.REPETITION]))
    frames[names.REPETITION] = frames[names.RUN_ID].map(numbering).astype(int)
    return frames
