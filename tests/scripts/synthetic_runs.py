"""Synthetic run directories for the compare and budget tests: the layout the
bench runner writes (manifest, frames/<config>-r<rep>.csv and .meta.json),
with frame times the test chooses, so every statistic has a known answer.

Every CSV column of the schema is written: the ones a test sets, the
configuration's columns, and the rest empty (float: not measured; the
optional columns: not applicable, no counters) or 0, so a column the schema
gains later does not break these runs. Counter columns are written where a
test gives their values (write_run_dir's `counters`).
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass, field
from pathlib import Path

from rtbench import atomic, load, names
from rtbench.run_status import ManifestStatus, RunStatus


@dataclass(frozen=True)
class SyntheticConfig:
    scene: str = "random20"
    renderer: str = "simd_tbb"
    threads: int = 2
    lanes: int = 16
    stage: str = "optimized"
    width: int = 96
    height: int = 72
    accel: str = names.BRUTE_FORCE
    traversal: str = ""
    hybrid_threshold: int | None = None
    gpu_bvh: str = ""
    gpu_schedule: str = ""
    gpu_path: str = ""
    gpu_rt_reorder: str = ""
    # "" as a CSV from before the precision axis would read (f32); else f32 or f16.
    precision: str = ""

    @property
    def id(self) -> str:
        retired = [v for c, (_, gone) in names.RETIRED_GPU_AXES.items() for v in gone if self.columns()[c] == v]
        accel = "".join(f"-{tag}" for tag in [*names.accel_tag(self.columns()), *retired])
        size = f"{self.width}x{self.height}"
        return f"{self.scene}-{self.renderer}-{self.stage}{accel}-t{self.threads}-l{self.lanes}-{size}"

    def columns(self) -> dict:
        stage = names.STAGES[self.stage]
        exits = names.EARLY_EXIT_SEPARATOR.join(stage["early_exits"]) or names.NO_EARLY_EXIT
        takes_threads = names.accepts(self.renderer, names.THREADS)
        return {
            names.SCENE: self.scene,
            names.RENDERER: self.renderer,
            names.THREADS: self.threads,
            names.LANES: self.lanes,
            names.SIMD_TARGET: "AVX3" if self.lanes > 1 else "",
            names.GRAIN: 1 if takes_threads else 0,
            names.PARTITION: "rows" if takes_threads else "",
            names.ALGORITHM: stage["algorithm"],
            names.EARLY_EXIT: exits,
            names.ACCEL: self.accel,
            names.TRAVERSAL: self.traversal,
            names.HYBRID_THRESHOLD: "" if self.hybrid_threshold is None else self.hybrid_threshold,
            names.GPU_BVH: self.gpu_bvh,
            names.GPU_SCHEDULE: self.gpu_schedule,
            names.GPU_PATH: self.gpu_path,
            names.GPU_RT_REORDER: self.gpu_rt_reorder,
            names.PRECISION: self.precision,
            names.WIDTH: self.width,
            names.HEIGHT: self.height,
        }


@dataclass
class Environment:
    """The host and build a run's metadata records."""

    cpu_model: str = "Synthetic CPU"
    logical_cores: int = 2
    compiler: str = "GNU 12.2.0"
    git_commit: str = "a" * 40
    device: str = "llvmpipe (LLVM 15.0.6, 256 bits)"
    build_type: str = "Release"
    compiler_flags: str = "-O3"
    libraries: dict = field(default_factory=lambda: {"onetbb": "2021.8.0"})


def csv_text(
    run_id: str,
    config: SyntheticConfig,
    render_ms: list[float],
    warmup: int,
    device: str,
    present_ms: float = 0.0,
    counters: dict[str, list] | None = None,
) -> str:
    """`counters`: counter column -> its value in each frame (none: the columns stay empty)."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(names.CSV_COLUMNS)
    for frame, ms in enumerate(render_ms):
        values = {
            **config.columns(),
            names.RUN_ID: run_id,
            names.FRAME: frame,
            names.WARMUP: int(frame < warmup),
            names.RENDER_MS: repr(float(ms)),
            "update_ms": "0",
            "present_ms": repr(float(present_ms)),
            "present": "none",
            names.DEVICE: device,
            **{column: frame_values[frame] for column, frame_values in (counters or {}).items()},
        }
        writer.writerow([values.get(c, _unset(c)) for c in names.CSV_COLUMNS])
    return out.getvalue()


def _unset(column: str):
    """What a column the test does not set holds: empty, or 0 for an int column that must have a value."""
    return 0 if names.COLUMN_TYPES[column] == "int" and column not in names.OPTIONAL_COLUMNS else ""


def agreement(within: float, psnr_db: float | None, max_difference: int) -> dict:
    """The metadata's agreement object of a run with --agreement (psnr_db None: identical images)."""
    return {
        "reference": "double",
        "frame": 0,
        "tolerance": 2,
        names.WITHIN_TOLERANCE: within,
        names.PSNR_DB: psnr_db,
        names.MAX_CHANNEL_DIFFERENCE: max_difference,
    }


def metadata(
    run_id: str, config: SyntheticConfig, warmup: int, measured: int, env: Environment, agreed: dict | None = None
) -> dict:
    """`agreed`: the agreement object (agreement()), None for a run without --agreement."""
    columns = config.columns()
    return {
        "schema_version": names.SCHEMA_VERSION,
        "run_id": run_id,
        "command_line": ["raytracer", "(synthetic)"],
        "scene": {"name": config.scene, "path": f"scenes/{config.scene}.json", "sha256": "0" * 64, "spheres": 20},
        "config": {
            **{
                k: columns[k]
                for k in (
                    names.RENDERER,
                    names.THREADS,
                    names.LANES,
                    names.SIMD_TARGET,
                    names.GRAIN,
                    names.PARTITION,
                    names.ALGORITHM,
                    names.EARLY_EXIT,
                    names.ACCEL,
                    names.WIDTH,
                    names.HEIGHT,
                )
            },
            "warmup_frames": warmup,
            "measured_frames": measured,
            "present": "none",
            "precision": names.precision_of(config.precision),
            "agreement": agreed is not None,
        },
        "agreement": agreed,
        "build": {
            "version": "0.0.0",
            "git_commit": env.git_commit,
            "git_dirty": False,
            "build_type": env.build_type,
            "compiler": env.compiler,
            "compiler_flags": env.compiler_flags,
            "nix": None,
        },
        "host": {"cpu_model": env.cpu_model, "logical_cores": env.logical_cores, "os": "Debian 12", "kernel": "Linux"},
        "libraries": env.libraries,
        "accel_structure": None,
        "device": {"name": env.device, "driver_name": "llvmpipe", "driver_version": "22.3.6"},
    }


def write_run_dir(
    out: Path,
    runs: dict[SyntheticConfig, list[list[float]]],
    warmup: int = 1,
    env: Environment | None = None,
    present_ms: float = 0.0,
    counters: dict[SyntheticConfig, dict[str, list]] | None = None,
    agreements: dict[SyntheticConfig, dict] | None = None,
    unavailable: dict[SyntheticConfig, str] | None = None,
) -> Path:
    """A run directory: for each configuration one run per list of render
    times (the first `warmup` of each are warm-up frames), every frame's
    Present phase taking `present_ms`; `counters`: for a configuration, each
    counter column's value per frame (the same in every repetition), and
    other per-frame columns such as gpu_ms likewise; `agreements`: a
    configuration's agreement object (agreement()); `unavailable`: configurations
    the bench's probe refused, with what the probe said (no data, one
    unavailable run each in the manifest)."""
    env = env or Environment()
    entries = []
    for config, repetitions in runs.items():
        for rep, times in enumerate(repetitions):
            index = len(entries)
            run_id = f"20260101T00{index // 60:02d}{index % 60:02d}Z-{index:06x}"
            stem = f"{load.FRAMES_DIR}/{config.id}-r{rep}"
            text = csv_text(run_id, config, times, warmup, env.device, present_ms, (counters or {}).get(config))
            atomic.write_text(out / f"{stem}.csv", text)
            agreed = (agreements or {}).get(config)
            atomic.write_json(
                out / f"{stem}{load.META_SUFFIX}", metadata(run_id, config, warmup, len(times) - warmup, env, agreed)
            )
            entries.append(
                {
                    "config": config.id,
                    "repetition": rep,
                    "renderer": config.renderer,
                    "csv": f"{stem}.csv",
                    "meta": f"{stem}{load.META_SUFFIX}",
                    "status": RunStatus.OK,
                }
            )
    for config, reason in (unavailable or {}).items():
        entries.append(
            {
                "config": config.id,
                "repetition": 0,
                "renderer": config.renderer,
                "status": RunStatus.UNAVAILABLE,
                "stderr_tail": reason,
            }
        )
    configs = [{"id": c.id, "renderer": c.renderer, "precision": c.precision} for c in [*runs, *(unavailable or {})]]
    atomic.write_json(
        out / load.MANIFEST,
        {
            "format": 1,
            "status": ManifestStatus.COMPLETE,
            "profile": {"name": "synthetic"},
            "host": {"cpu_governors": ["performance"]},
            "configs": configs,
            "runs": entries,
        },
    )
    return out


def table_rows(markdown: str) -> list[list[str]]:
    """The body rows of the one Markdown table in `markdown`, as cells."""
    lines = [line for line in markdown.splitlines() if line.startswith("|")]
    return [[cell.strip() for cell in line.strip("|").split("|")] for line in lines[2:]]
