"""Runs a schedule of configurations, each as its own raytracer process, and
keeps a manifest of what happened.

The manifest (RUN_DIR/manifest.json) is rewritten atomically after every
run, so whatever stops the runner (a failure, Ctrl-C, a killed terminal)
leaves a directory that describes itself: every finished run's CSV and
metadata, and for the others their status, exit code and the tail of their
stderr.
"""

from __future__ import annotations

import json
import os
import platform
import subprocess
import time
from dataclasses import asdict, dataclass, field
from datetime import datetime, timezone
from pathlib import Path

from rtbench import atomic, load, names, noise, profiles, scenes
from rtbench.profiles import Config, Profile

PENDING, OK, FAILED, UNAVAILABLE, INTERRUPTED = "pending", load.OK, "failed", "unavailable", "interrupted"
STDERR_TAIL_CHARS = 2000
MANIFEST_FORMAT = 1


class BuildError(RuntimeError):
    """The binary could not be built; carries the build's output tail."""


@dataclass
class RunRecord:
    """One run of one configuration (one repetition), as the manifest lists it."""

    index: int
    config: str
    repetition: int
    renderer: str
    csv: str
    meta: str
    argv: list[str]
    status: str = PENDING
    exit_code: int | None = None
    seconds: float | None = None
    stderr_tail: str = ""


@dataclass
class Manifest:
    """Everything the run directory says about itself."""

    profile: Profile
    configs: list[Config]
    runs: list[RunRecord]
    binary: str
    command_line: list[str]
    host: dict
    warnings: list[str] = field(default_factory=list)
    status: str = "running"
    started_at: str = ""
    finished_at: str | None = None

    def to_json(self) -> dict:
        return {
            "format": MANIFEST_FORMAT,
            "status": self.status,
            "started_at": self.started_at,
            "finished_at": self.finished_at,
            "profile": {"name": self.profile.name, "path": str(self.profile.path), "description": self.profile.description,
                        "preset": self.profile.preset, "repetitions": len({r.repetition for r in self.runs}),
                        "interleave": self.profile.interleave, "definition": self.profile.raw},
            "binary": self.binary,
            "command_line": self.command_line,
            "host": self.host,
            "warnings": self.warnings,
            "counts": self.counts(),
            "configs": [c.describe() for c in self.configs],
            "runs": [asdict(r) for r in self.runs],
        }

    def counts(self) -> dict[str, int]:
        counts: dict[str, int] = {}
        for r in self.runs:
            counts[r.status] = counts.get(r.status, 0) + 1
        return counts


def utc_now() -> str:
    return datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")


def write_manifest(run_dir: Path, manifest: Manifest) -> Path:
    return atomic.write_json(run_dir / load.MANIFEST, manifest.to_json())


# --- building -------------------------------------------------------------------

def configure_presets(repo_root: Path) -> list[str]:
    """The visible configure presets of CMakePresets.json."""
    data = json.loads((repo_root / "CMakePresets.json").read_text(encoding="utf-8"))
    return [p["name"] for p in data.get("configurePresets", []) if not p.get("hidden")]


def build(preset: str, repo_root: Path, jobs: int) -> Path:
    """Configures (once) and builds a preset; returns its raytracer binary.
    Ninja makes an up-to-date build a no-op, so this is cheap when nothing changed."""
    if preset not in configure_presets(repo_root):
        raise BuildError(f"CMakePresets.json has no preset {preset!r} (presets: {', '.join(configure_presets(repo_root))})")
    build_dir = repo_root / "build" / preset
    steps = []
    if not (build_dir / "build.ninja").is_file():
        steps.append(["cmake", "--preset", preset])
    steps.append(["cmake", "--build", "--preset", preset, f"-j{jobs}", "--target", "raytracer"])
    for step in steps:
        done = subprocess.run(step, cwd=repo_root, capture_output=True, text=True)
        if done.returncode != 0:
            raise BuildError(f"`{' '.join(step)}` failed:\n{(done.stdout + done.stderr)[-4000:]}")
    binary = build_dir / "raytracer"
    if not binary.is_file():
        raise BuildError(f"the build of preset {preset} did not produce {binary}")
    return binary


# --- running ----------------------------------------------------------------------

def make_run_dir(runs_dir: Path, profile_name: str, now: datetime | None = None) -> Path:
    """runs/<UTC timestamp>-<profile>/, never reusing an existing directory."""
    stamp = (now or datetime.now(timezone.utc)).strftime("%Y%m%dT%H%M%SZ")
    runs_dir.mkdir(parents=True, exist_ok=True)
    for suffix in ["", *(f"-{i}" for i in range(2, 1000))]:
        path = runs_dir / f"{stamp}-{profile_name}{suffix}"
        try:
            path.mkdir()
            (path / load.FRAMES_DIR).mkdir()
            return path
        except FileExistsError:
            continue
    raise RuntimeError(f"cannot create a run directory under {runs_dir}")


def write_generated_scenes(configs: list[Config], run_dir: Path, out=None) -> list[Config]:
    """Writes the generated scenes the configurations use (randomN that
    scenes/ lacks) into RUN_DIR/scenes/ and returns the configurations with
    those paths in place of the stand-in."""
    written = {}
    for name in profiles.generated_scenes(configs):
        scene = scenes.recipe(name)()
        path = atomic.write_text(run_dir / profiles.GENERATED_SCENES.name / f"{name}.json", scenes.to_json(scene))
        written[str(profiles.GENERATED_SCENES / f"{name}.json")] = str(path.resolve())
        if out is not None:
            print(f"bench: generated scene {name} ({len(scene['spheres'])} spheres) -> {path}", file=out, flush=True)
    return profiles.place_generated_scenes(configs, written)


def plan_runs(schedule: list[tuple[int, Config]], binary: Path, run_dir: Path) -> list[RunRecord]:
    """A record (status pending) with its command line for every scheduled run."""
    records = []
    for index, (rep, config) in enumerate(schedule):
        stem = f"{load.FRAMES_DIR}/{config.id}-r{rep}"
        csv, meta = f"{stem}.csv", f"{stem}{load.META_SUFFIX}"
        argv = config.argv(binary, run_dir / csv, run_dir / meta)
        records.append(RunRecord(index, config.id, rep, config.renderer, csv, meta, argv))
    return records


def probe_renderer(binary: Path, renderer: str, scene_path: str, cwd: Path, timeout: float = 120) -> str | None:
    """None if the binary can run `renderer` at all (a 4x4 frame), else why not
    (e.g. 'not built' in this build, or no Vulkan device)."""
    argv = [str(binary), names.RENDERER_FLAGS[renderer], scene_path, "--width", "4", "--height", "4",
            "--warmup", "0", "--frames", "1", "--quiet"]
    try:
        done = subprocess.run(argv, cwd=cwd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return f"a 4x4 test frame did not finish in {timeout:.0f} s"
    if done.returncode == 0:
        return None
    return f"exit {done.returncode}: {_tail(done.stderr or done.stdout)}"


def _tail(text: str) -> str:
    return text.strip()[-STDERR_TAIL_CHARS:]


def run_one(record: RunRecord, run_dir: Path, cwd: Path, timeout: float) -> RunRecord:
    """Runs one configuration's process and records how it ended. A
    KeyboardInterrupt propagates (subprocess kills the child first)."""
    started = time.monotonic()
    try:
        done = subprocess.run(record.argv, cwd=cwd, capture_output=True, text=True, timeout=timeout)
        record.exit_code, record.stderr_tail = done.returncode, _tail(done.stderr)
        complete = (run_dir / record.csv).is_file() and (run_dir / record.meta).is_file()
        record.status = OK if done.returncode == 0 and complete else FAILED
        if done.returncode == 0 and not complete:
            record.stderr_tail = (record.stderr_tail + "\nexit 0 but the CSV or metadata is missing").strip()
    except subprocess.TimeoutExpired as e:
        record.status, record.stderr_tail = FAILED, f"timed out after {timeout:.0f} s\n" + _tail(_text(e.stderr))
    finally:
        record.seconds = round(time.monotonic() - started, 3)
        remove_temporaries(run_dir, record)
    return record


def _text(data) -> str:
    if data is None:
        return ""
    return data.decode(errors="replace") if isinstance(data, bytes) else data


def remove_temporaries(run_dir: Path, record: RunRecord) -> None:
    """The raytracer writes FILE.tmp.<pid> and renames it; a killed process can
    leave one behind."""
    for rel in (record.csv, record.meta):
        target = run_dir / rel
        for leftover in target.parent.glob(target.name + ".tmp.*"):
            leftover.unlink(missing_ok=True)


def host_info() -> dict:
    """What the runner knows about the machine at the start (each run's
    metadata sidecar records more: CPU model, OS, build)."""
    return {
        "logical_cores": os.cpu_count(), "platform": platform.platform(), "python": platform.python_version(),
        "cpu_governors": sorted(set(noise.read_governors().values())), "load_average_1min": noise.read_load_average(),
    }


class Observer:
    """Progress callbacks; the base class stays silent."""

    def started(self, record: RunRecord, done: int, total: int) -> None: ...
    def finished(self, record: RunRecord, done: int, total: int) -> None: ...


def execute(manifest: Manifest, run_dir: Path, cwd: Path, timeout: float, observer: Observer) -> bool:
    """Runs every pending record in order, rewriting the manifest after each;
    the observer counts the runs this call executes (unavailable ones are not
    among them). Returns False if interrupted (Ctrl-C or SIGTERM): the record
    in flight is marked interrupted, the ones after it stay pending, the
    manifest is written."""
    todo = [r for r in manifest.runs if r.status == PENDING]
    current = None
    try:
        for done, record in enumerate(todo):
            current = record
            observer.started(record, done, len(todo))
            run_one(record, run_dir, cwd, timeout)
            observer.finished(record, done + 1, len(todo))
            current = None
            write_manifest(run_dir, manifest)
    except KeyboardInterrupt:
        if current is not None:
            current.status = INTERRUPTED
            remove_temporaries(run_dir, current)
        manifest.status = INTERRUPTED
        manifest.finished_at = utc_now()
        write_manifest(run_dir, manifest)
        return False
    manifest.status = "complete"
    manifest.finished_at = utc_now()
    write_manifest(run_dir, manifest)
    return True
