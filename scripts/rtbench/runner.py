"""Runs a schedule of configurations, each as its own raytracer process, and
keeps a manifest of what happened.

The manifest (RUN_DIR/manifest.json) is rewritten atomically after every
run, so whatever stops the runner (a failure, Ctrl-C, a killed terminal)
leaves a directory that describes itself: every finished run's CSV and
metadata, and for the others their status, exit code and the tail of their
stderr. A run directory is locked while a runner works in it (RUN_DIR/bench.lock,
an flock that dies with its process), so two runners never write into one
directory; an interrupted run is resumed from its manifest (resume_manifest).
"""

from __future__ import annotations

import fcntl
import hashlib
import json
import os
import platform
import signal
import subprocess
import time
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field
from datetime import datetime, timezone
from pathlib import Path

from rtbench import atomic, load, names, noise, profiles, progress, scenes
from rtbench.profiles import Config, Profile

PENDING, OK, FAILED, UNAVAILABLE, INTERRUPTED = load.PENDING, load.OK, "failed", "unavailable", load.INTERRUPTED
RUNNING, COMPLETE = "running", load.COMPLETE
STDERR_TAIL_CHARS = 2000
MANIFEST_FORMAT = 1
LOCK_FILE = "bench.lock"


class RunDirBusy(RuntimeError):
    """Another runner holds the run directory's lock."""


class ResumeError(ValueError):
    """A run directory that cannot be resumed as asked; the message says why."""


class Interrupted(KeyboardInterrupt):
    """Ctrl-C (SIGINT) or SIGTERM: stop after killing the running
    configuration. A KeyboardInterrupt, so every `except KeyboardInterrupt`
    cleans up the same way for both signals."""

    def __init__(self, signum: int = signal.SIGINT):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


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
    status: str = RUNNING
    started_at: str = ""
    finished_at: str | None = None
    identity: dict = field(default_factory=dict)  # sha256 of the binary and of every scene file
    interrupted_by: str | None = None
    resumed: list[dict] = field(default_factory=list)

    @classmethod
    def start(cls, profile: Profile, configs: list[Config], runs: list[RunRecord], binary: Path,
              command_line: list[str], host: dict, warnings: list[str]) -> "Manifest":
        """The manifest of a new run (status running), with the identity of
        what it runs, which a resume checks."""
        section = {"name": profile.name, "path": str(profile.path), "description": profile.description,
                   "preset": profile.preset, "repetitions": len({r.repetition for r in runs}),
                   "interleave": profile.interleave, "timeout_s": profile.timeout_s, "definition": profile.raw}
        described = [c.describe() for c in configs]
        identity = run_identity(binary, [c["scene_path"] for c in described])
        return cls(section, described, runs, str(binary), command_line, host, warnings, started_at=utc_now(),
                   identity=identity)

    @classmethod
    def from_json(cls, data: dict) -> "Manifest":
        runs = [RunRecord(**r) for r in data["runs"]]
        return cls(data["profile"], data["configs"], runs, data["binary"], data["command_line"], data["host"],
                   data.get("warnings", []), data["status"], data.get("started_at", ""), data.get("finished_at"),
                   data.get("identity", {}), data.get("interrupted_by"), data.get("resumed", []))

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
    return datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")


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
    return {"binary_sha256": file_sha256(binary),
            "scene_sha256": {p: file_sha256(Path(p)) for p in sorted(set(scene_paths))}}


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
            raise RunDirBusy(f"{run_dir}: in use by another bench process (pid {holder}); "
                             "wait for it to finish or stop it first") from None
        os.ftruncate(fd, 0)
        os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
        yield
    finally:
        os.close(fd)


# --- building -------------------------------------------------------------------

def configure_presets(repo_root: Path) -> list[str]:
    """The visible configure presets of CMakePresets.json."""
    data = json.loads((repo_root / "CMakePresets.json").read_text(encoding="utf-8"))
    return [p["name"] for p in data.get("configurePresets", []) if not p.get("hidden")]


def build(preset: str, repo_root: Path, jobs: int, out=None) -> Path:
    """Configures (once) and builds a preset; returns its raytracer binary.
    Ninja makes an up-to-date build a no-op, so this is cheap when nothing
    changed. Prints one line per step to `out` (a build's every 10 %,
    rtbench.progress); a failed step's BuildError carries its whole output."""
    if preset not in configure_presets(repo_root):
        raise BuildError(f"CMakePresets.json has no preset {preset!r} (presets: {', '.join(configure_presets(repo_root))})")
    build_dir = repo_root / "build" / preset
    steps = []
    if not (build_dir / "build.ninja").is_file():
        steps.append((f"configuring preset {preset}", ["cmake", "--preset", preset], False))
    steps.append((f"building preset {preset}",
                  ["cmake", "--build", "--preset", preset, f"-j{jobs}", "--target", "raytracer"], True))
    for label, argv, is_build in steps:
        _build_step(label, argv, is_build, repo_root, out)
    binary = build_dir / "raytracer"
    if not binary.is_file():
        raise BuildError(f"the build of preset {preset} did not produce {binary}")
    return binary


def _build_step(label: str, argv: list[str], is_build: bool, cwd: Path, out) -> None:
    """One line (a build: one every 10 % and a last one), the output kept for the error."""
    show = progress.BuildProgress(f"bench: {label}")
    if not is_build:
        print(f"bench: {label}", file=out, flush=True)
    lines = []
    proc = subprocess.Popen(argv, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            errors="replace")
    try:
        for line in proc.stdout:
            lines.append(line)
            message = show.feed(line)
            if message:
                print(message, file=out, flush=True)
        proc.wait()
    except BaseException:
        proc.kill()
        proc.wait()
        raise
    if is_build:
        print(show.summary(), file=out, flush=True)
    if proc.returncode != 0:
        raise BuildError(f"`{' '.join(argv)}` failed (exit {proc.returncode}); its whole output:\n{''.join(lines)}")


# --- running ----------------------------------------------------------------------

def make_run_dir(runs_dir: Path, profile_name: str, now: datetime | None = None) -> Path:
    """runs/<UTC timestamp>-<profile>/, never reusing an existing directory:
    mkdir either creates the directory or fails, so two runners started in
    the same second get -2, -3, ... instead of sharing one."""
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
        code, out, err = run_process(argv, cwd, timeout)
    except subprocess.TimeoutExpired:
        return f"a 4x4 test frame did not finish in {timeout:.0f} s"
    if code == 0:
        return None
    return f"exit {code}: {_tail(err or out)}"


def _tail(text: str) -> str:
    return text.strip()[-STDERR_TAIL_CHARS:]


def run_process(argv: list[str], cwd: Path, timeout: float) -> tuple[int, str, str]:
    """Runs a process in a process group of its own and returns (exit code,
    stdout, stderr). Whatever ends the wait (the timeout, Ctrl-C, SIGTERM)
    kills the whole group with SIGKILL and reaps it before propagating, so
    nothing it started keeps running. Its own group also keeps a terminal's
    Ctrl-C from reaching it before the runner has decided what to do."""
    proc = subprocess.Popen(argv, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired as e:
        _kill_group(proc)
        _, err = proc.communicate()
        e.stderr = err
        raise
    except BaseException:
        _kill_group(proc)
        proc.communicate()
        raise
    return proc.returncode, out, err


def _kill_group(proc: subprocess.Popen) -> None:
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except ProcessLookupError:  # the group is gone already
        pass


def run_one(record: RunRecord, run_dir: Path, cwd: Path, timeout: float) -> RunRecord:
    """Runs one configuration's process and records how it ended. A
    KeyboardInterrupt propagates after the process group is killed."""
    started = time.monotonic()
    try:
        code, _, err = run_process(record.argv, cwd, timeout)
        record.exit_code, record.stderr_tail = code, _tail(err)
        complete = (run_dir / record.csv).is_file() and (run_dir / record.meta).is_file()
        record.status = OK if code == 0 and complete else FAILED
        if code == 0 and not complete:
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
    in flight is marked interrupted (its process group killed), the ones
    after it stay pending, the manifest is written with what is missing."""
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
    except KeyboardInterrupt as e:
        if current is not None:
            current.status, current.exit_code, current.stderr_tail = INTERRUPTED, None, ""
            discard_outputs(run_dir, current)
        mark_interrupted(run_dir, manifest, e)
        return False
    manifest.status = COMPLETE
    manifest.finished_at = utc_now()
    write_manifest(run_dir, manifest)
    return True


def mark_interrupted(run_dir: Path, manifest: Manifest, interrupt: KeyboardInterrupt) -> None:
    manifest.status, manifest.finished_at = INTERRUPTED, utc_now()
    manifest.interrupted_by = signal.Signals(getattr(interrupt, "signum", signal.SIGINT)).name
    write_manifest(run_dir, manifest)


def discard_outputs(run_dir: Path, record: RunRecord) -> None:
    """A run that did not finish keeps no output: the raytracer renames its
    CSV before its metadata, so a kill between the two could leave a CSV
    without its sidecar."""
    remove_temporaries(run_dir, record)
    for rel in (record.csv, record.meta):
        (run_dir / rel).unlink(missing_ok=True)


@contextmanager
def interruptible():
    """SIGINT (Ctrl-C) and SIGTERM raise Interrupted inside the block, the
    first one only: a second signal while the runner kills the running
    configuration and writes the manifest is ignored, so that cleanup
    finishes."""
    raised = False

    def handler(signum, frame):
        nonlocal raised
        if not raised:
            raised = True
            raise Interrupted(signum)

    previous = {s: signal.signal(s, handler) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for s, h in previous.items():
            signal.signal(s, h)


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
        if r.status in (PENDING, INTERRUPTED):
            discard_outputs(run_dir, r)
            r.status, r.exit_code, r.seconds, r.stderr_tail = PENDING, None, None, ""
            r.argv = [str(target), *r.argv[1:]]
    manifest.binary = str(target)
    manifest.status, manifest.finished_at, manifest.interrupted_by = RUNNING, None, None
    return manifest


def _check_identity(run_dir: Path, manifest: Manifest, binary: Path) -> None:
    recorded = manifest.identity.get("binary_sha256")
    if not recorded:
        raise ResumeError(f"{run_dir / load.MANIFEST}: records no binary identity (written by an older runner)")
    if not binary.is_file():
        raise ResumeError(f"{run_dir}: the run's binary {binary} is gone; rebuild it or pass --binary")
    if file_sha256(binary) != recorded:
        raise ResumeError(f"{run_dir}: {binary} is not the build this run started with (sha256 differs); "
                          "resuming would mix two builds in one run. Start a new run instead")
    for path, digest in manifest.identity.get("scene_sha256", {}).items():
        if not Path(path).is_file() or file_sha256(Path(path)) != digest:
            raise ResumeError(f"{run_dir}: scene {path} is missing or changed since the run started; "
                              "start a new run instead")
