"""The run directory and its manifest: where a bench run's files go, what
the directory says about itself, and how an unfinished run is resumed.

The manifest (RUN_DIR/manifest.json) is rewritten atomically after every
run, so whatever stops the runner (a failure, Ctrl-C, a killed terminal)
leaves a directory that describes itself: every finished run's CSV and
metadata, and for the others their status, exit code and the tail of their
stderr. A run directory is locked while a runner works in it (RUN_DIR/bench.lock,
an flock that dies with its process), so two runners never write into one
directory; an interrupted run is resumed from its manifest (resume_manifest).
The status words are rtbench.run_status's.
"""

from __future__ import annotations

import fcntl
import hashlib
import os
import platform
import signal
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field
from datetime import UTC, datetime
from pathlib import Path

from rtbench import atomic, configurations, emulation, load, noise, profiles, scenes
from rtbench.configurations import Config
from rtbench.profiles import Profile
from rtbench.run_status import NOT_RUN, ManifestStatus, RunStatus

MANIFEST_FORMAT = 1
LOCK_FILE = "bench.lock"


class RunDirBusy(RuntimeError):
    """Another runner holds the run directory's lock."""


class ResumeError(ValueError):
    """A run directory that cannot be resumed as asked; the message says why."""


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
    status: str = RunStatus.PENDING
    exit_code: int | None = None
    seconds: float | None = None
    stderr_tail: str = ""


@dataclass
class Manifest:
    """Everything the run directory says about itself. The profile and the
    configurations are kept as the plain data the manifest file holds, so a
    manifest read back from disk (resume_manifest) is the same object."""

    profile: dict
    configs: list[dict]
    runs: list[RunRecord]
    binary: str
    command_line: list[str]
    host: dict
    warnings: list[str] = field(default_factory=list)
    status: str = ManifestStatus.RUNNING
    started_at: str = ""
    finished_at: str | None = None
    identity: dict = field(default_factory=dict)  # sha256 of the binary and of every scene file
    interrupted_by: str | None = None
    resumed: list[dict] = field(default_factory=list)

    @classmethod
    def start(
        cls,
        profile: Profile,
        configs: list[Config],
        runs: list[RunRecord],
        binary: Path,
        command_line: list[str],
        host: dict,
        warnings: list[str],
    ) -> Manifest:
        """The manifest of a new run (status running), with the identity of
        what it runs, which a resume checks."""
        section = {
            "name": profile.name,
            "path": str(profile.path),
            "description": profile.description,
            "preset": profile.preset,
            "repetitions": len({r.repetition for r in runs}),
            "interleave": profile.interleave,
            "timeout_s": profile.timeout_s,
            "definition": profile.raw,
        }
        described = [c.describe() for c in configs]
        identity = run_identity(binary, [c["scene_path"] for c in described])
        return cls(
            section, described, runs, str(binary), command_line, host, warnings, started_at=utc_now(), identity=identity
        )

    @classmethod
    def from_json(cls, data: dict) -> Manifest:
        runs = [RunRecord(**r) for r in data["runs"]]
        return cls(
            data["profile"],
            data["configs"],
            runs,
            data["binary"],
            data["command_line"],
            data["host"],
            data.get("warnings", []),
            data["status"],
            data.get("started_at", ""),
            data.get("finished_at"),
            data.get("identity", {}),
            data.get("interrupted_by"),
            data.get("resumed", []),
        )

    def to_json(self) -> dict:
        return {
            "format": MANIFEST_FORMAT,
            "status": self.status,
            "started_at": self.started_at,
            "finished_at": self.finished_at,
            "interrupted_by": self.interrupted_by,
            "resumed": self.resumed,
            "profile": self.profile,
            "binary": self.binary,
            "identity": self.identity,
            "command_line": self.command_line,
            "host": self.host,
            "warnings": self.warnings,
            "counts": self.counts(),
            "missing": self.missing(),
            "configs": self.configs,
            "runs": [asdict(r) for r in self.runs],
        }

    def counts(self) -> dict[str, int]:
        counts: dict[str, int] = {}
        for r in self.runs:
            counts[r.status] = counts.get(r.status, 0) + 1
        return counts

    def missing(self) -> dict[str, list[int]]:
        """Configuration id -> the repetitions still to run: what `--resume` would run."""
        return load.missing_runs({"runs": [asdict(r) for r in self.runs]})


def utc_now() -> str:
    return datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ")


def write_manifest(run_dir: Path, manifest: Manifest) -> Path:
    return atomic.write_json(run_dir / load.MANIFEST, manifest.to_json())


def file_sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def run_identity(binary: Path, scene_paths: list[str]) -> dict:
    """What the numbers of a run depend on besides the command lines: the
    binary's and the scenes' contents. A resume that would mix builds or
    edited scenes into one run is refused on these."""
    return {
        "binary_sha256": file_sha256(binary),
        "scene_sha256": {p: file_sha256(Path(p)) for p in sorted(set(scene_paths))},
    }


# --- the run directory's lock ---------------------------------------------------


@contextmanager
def run_dir_lock(run_dir: Path):
    """Holds RUN_DIR/bench.lock (an exclusive flock) for the block. The kernel
    drops it when the process dies however it dies, so a stale lock cannot
    outlive a killed runner; a second runner gets RunDirBusy at once."""
    path = run_dir / LOCK_FILE
    fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o644)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.pread(fd, 64, 0).decode(errors="replace").strip() or "?"
            raise RunDirBusy(
                f"{run_dir}: in use by another bench process (pid {holder}); wait for it to finish or stop it first"
            ) from None
        os.ftruncate(fd, 0)
        os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
        yield
    finally:
        os.close(fd)


# --- the run directory's files ---------------------------------------------------


def make_run_dir(runs_dir: Path, profile_name: str, now: datetime | None = None) -> Path:
    """runs/<UTC timestamp>-<profile>/, never reusing an existing directory:
    mkdir either creates the directory or fails, so two runners started in
    the same second get -2, -3, ... instead of sharing one."""
    stamp = (now or datetime.now(UTC)).strftime("%Y%m%dT%H%M%SZ")
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
    for name in configurations.generated_scenes(configs):
        scene = scenes.recipe(name)()
        path = atomic.write_text(run_dir / profiles.GENERATED_SCENES.name / f"{name}.json", scenes.to_json(scene))
        written[str(profiles.GENERATED_SCENES / f"{name}.json")] = str(path.resolve())
        if out is not None:
            print(f"bench: generated scene {name} ({len(scene['spheres'])} spheres) -> {path}", file=out, flush=True)
    return configurations.place_generated_scenes(configs, written)


def plan_runs(schedule: list[tuple[int, Config]], binary: Path, run_dir: Path) -> list[RunRecord]:
    """A record (status pending) with its command line for every scheduled run."""
    records = []
    for index, (rep, config) in enumerate(schedule):
        stem = f"{load.FRAMES_DIR}/{config.id}-r{rep}"
        csv, meta = f"{stem}.csv", f"{stem}{load.META_SUFFIX}"
        argv = config.argv(binary, run_dir / csv, run_dir / meta)
        records.append(RunRecord(index, config.id, rep, config.renderer, csv, meta, argv))
    return records


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
        "logical_cores": os.cpu_count(),
        "platform": platform.platform(),
        "python": platform.python_version(),
        "cpu_governors": sorted(set(noise.read_governors().values())),
        "load_average_1min": noise.read_load_average(),
    }


def mark_interrupted(run_dir: Path, manifest: Manifest, interrupt: KeyboardInterrupt) -> None:
    manifest.status, manifest.finished_at = ManifestStatus.INTERRUPTED, utc_now()
    manifest.interrupted_by = signal.Signals(getattr(interrupt, "signum", signal.SIGINT)).name
    write_manifest(run_dir, manifest)


def discard_outputs(run_dir: Path, record: RunRecord) -> None:
    """A run that did not finish keeps no output: the raytracer renames its
    CSV before its metadata, so a kill between the two could leave a CSV
    without its sidecar."""
    remove_temporaries(run_dir, record)
    for rel in (record.csv, record.meta):
        (run_dir / rel).unlink(missing_ok=True)


# --- resuming ----------------------------------------------------------------------


def resume_manifest(run_dir: Path, binary: Path | None) -> Manifest:
    """The manifest of an unfinished run, ready to run what is missing: its
    interrupted run back to pending, the binary (the recorded one, or
    `binary` if given) checked to be the same build and every scene
    unchanged. ResumeError says why a run cannot be resumed."""
    data = load.read_manifest(run_dir) if run_dir.is_dir() else None
    if data is None:
        raise ResumeError(f"{run_dir}: no {load.MANIFEST}; not a run directory written by scripts/bench")
    try:
        manifest = Manifest.from_json(data)
    except (KeyError, TypeError) as e:
        raise ResumeError(f"{run_dir / load.MANIFEST}: not a manifest this runner can resume ({e})") from None
    if not manifest.missing():
        raise ResumeError(f"{run_dir}: nothing to resume, every run has finished (status {manifest.status})")
    target = Path(binary or manifest.binary).resolve()
    _check_identity(run_dir, manifest, target)
    for r in manifest.runs:
        if r.status in NOT_RUN:
            discard_outputs(run_dir, r)
            r.status, r.exit_code, r.seconds, r.stderr_tail = RunStatus.PENDING, None, None, ""
            r.argv = [str(target), *r.argv[1:]]
    manifest.binary = str(target)
    manifest.status, manifest.finished_at, manifest.interrupted_by = ManifestStatus.RUNNING, None, None
    return manifest


def _check_identity(run_dir: Path, manifest: Manifest, binary: Path) -> None:
    recorded = manifest.identity.get("binary_sha256")
    if not recorded:
        raise ResumeError(f"{run_dir / load.MANIFEST}: records no binary identity (written by an older runner)")
    if not binary.is_file():
        raise ResumeError(f"{run_dir}: the run's binary {binary} is gone; rebuild it or pass --binary")
    if reason := emulation.foreign_binary_reason(binary):
        raise ResumeError(f"{run_dir}: {reason}")
    if file_sha256(binary) != recorded:
        raise ResumeError(
            f"{run_dir}: {binary} is not the build this run started with (sha256 differs); "
            "resuming would mix two builds in one run. Start a new run instead"
        )
    for path, digest in manifest.identity.get("scene_sha256", {}).items():
        if not Path(path).is_file() or file_sha256(Path(path)) != digest:
            raise ResumeError(
                f"{run_dir}: scene {path} is missing or changed since the run started; start a new run instead"
            )
