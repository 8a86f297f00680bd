"""Runs a benchmark profile: every configuration as its own raytracer process,
renderers interleaved across repetitions, results in runs/<UTC time>-<profile>/,
then a report of that run.

    scripts/bench                      # the `paper` profile on its scenes
    scripts/bench random100            # the `paper` profile on scenes/random100.json
    scripts/bench --profile quick      # seconds; what the tests run
    scripts/bench --profile scaling random100 --no-report
    scripts/bench --resume runs/20250101T120000Z-paper   # finish an interrupted run

A scene given by name means scenes/NAME.json; a path works too. The release
binary (or the profile's preset) is built first unless --binary names one.
Renderers this binary does not have are reported and skipped; a failing
configuration is reported and the others still run.

Ctrl-C (SIGINT) or SIGTERM kills the running configuration's process group,
keeps every finished run and writes the manifest, marked interrupted with
the runs still missing; `--resume RUN_DIR` runs those (with the same binary
and scenes, which it checks) and then reports. A run directory is locked
while a runner works in it: two runners never write into one directory.

Exit status: 0 all runs finished (skipped renderers aside), 1 a run failed,
nothing ran or the run directory is in use, 2 bad arguments, profile or run
directory to resume, 130 interrupted by SIGINT, 143 by SIGTERM.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import sys
import time
import traceback
from pathlib import Path

from rtbench import builder, cli, configurations, emulation, manifests, names, noise, profiles, runner
from rtbench.profiles import ProfileError
from rtbench.run_status import ManifestStatus, RunStatus

DEFAULT_PROFILE = "paper"


def default_runs_dir() -> Path:
    return names.REPO_ROOT / "runs" if os.access(names.REPO_ROOT, os.W_OK) else Path.cwd() / "runs"


def binary_from_environment(preset: str) -> Path | None:
    """A prebuilt binary handed over by the environment (the Nix apps do)."""
    value = os.environ.get("RT_BINARY_PAPER_O0" if preset == "paper-o0" else "RT_BINARY")
    return Path(value) if value else None


def parse_args(argv: list[str] | None, prog: str = "bench") -> argparse.Namespace:
    p = cli.command_parser(prog, __doc__)
    p.add_argument("scenes", nargs="*", metavar="SCENE", help="scene names or files (default: the profile's scenes)")
    p.add_argument("-p", "--profile", help="profile name (profiles/NAME.toml) or file; default paper")
    p.add_argument(
        "--resume",
        type=Path,
        metavar="RUN_DIR",
        help="run what an interrupted run left (its own plan; the binary and scenes must be unchanged), then report",
    )
    p.add_argument(
        "--binary",
        type=Path,
        help="use this raytracer binary, build nothing (default: $RT_BINARY, or $RT_BINARY_PAPER_O0 "
        "for a paper-o0 profile, when set, as under Nix)",
    )
    p.add_argument("--preset", help="CMake preset to build (default: the profile's, usually release)")
    p.add_argument(
        "--renderer",
        action="append",
        dest="renderers",
        metavar="NAME",
        choices=names.RENDERERS,
        help="only this renderer (repeatable)",
    )
    for key in ("width", "height", "warmup", "frames", "repetitions"):
        p.add_argument(f"--{key}", type=int, metavar="N", help=f"override the profile's {key}")
    p.add_argument(
        "--runs-dir",
        type=Path,
        default=default_runs_dir(),
        help="where run directories go (default: runs/ in the repository, or in the current directory "
        "when the repository is read-only, as in the Nix store)",
    )
    p.add_argument("--report-dir", type=Path, help="report output (default: RUN_DIR/report)")
    p.add_argument("--no-report", action="store_true", help="do not make the report (scripts/report.py) at the end")
    p.add_argument("--dry-run", action="store_true", help="print the schedule and exit")
    p.add_argument("--plain", action="store_true", help="plain progress lines even on a terminal")
    p.add_argument("-j", "--jobs", type=int, default=os.cpu_count() or 1, help="build parallelism (default: all cores)")
    args = p.parse_args(argv)
    for key in ("width", "height", "frames", "repetitions"):
        if getattr(args, key) is not None and getattr(args, key) < 1:
            p.error(f"--{key} must be at least 1")
    if args.warmup is not None and args.warmup < 0:
        p.error("--warmup must not be negative")
    if args.resume:
        planning = {
            "SCENE": args.scenes,
            "--renderer": args.renderers,
            "--preset": args.preset,
            "--dry-run": args.dry_run,
            **{f"--{k}": getattr(args, k) for k in PLAN_OVERRIDES},
        }
        given = [name for name, value in planning.items() if value]
        if given:
            p.error(f"--resume continues the run's own plan; it cannot be changed with {', '.join(given)}")
    return args


PLAN_OVERRIDES = ("width", "height", "warmup", "frames", "repetitions")


def plan(
    args: argparse.Namespace,
) -> tuple[profiles.Profile, list[configurations.Config], list[tuple[int, configurations.Config]]]:
    """The profile, its configurations and the run order, with the command
    line's scenes, renderer filter and overrides applied."""
    profile = profiles.load_profile(args.profile or DEFAULT_PROFILE)
    host = emulation.host_architecture()
    if profile.architecture and profile.architecture != host:
        raise ProfileError(
            f"{profile.path}: architecture = {profile.architecture!r}, and this machine is {host}: the profile "
            f"measures an {profile.architecture} CPU natively; run it on one"
        )
    scenes = [profiles.resolve_scene(s) for s in (args.scenes or profile.scenes)]
    forced = {k: getattr(args, k) for k in ("width", "height", "warmup", "frames") if getattr(args, k) is not None}
    configs = configurations.expand(profile, scenes, os.cpu_count() or 1, args.renderers, forced)
    if not configs:
        raise ProfileError(f"{profile.path}: no configuration left (renderer filter {args.renderers})")
    repetitions = args.repetitions or profile.repetitions
    order = configurations.schedule(configs, repetitions, profile.interleave, profile.seed)
    return profile, configs, order


class PlainObserver(runner.Observer):
    """One line per finished run, with an ETA from the mean duration so far:
    for logs and CI, where a live bar would be noise."""

    def __init__(self, stream=sys.stdout):
        self.stream, self.t0 = stream, time.monotonic()

    def finished(self, record, done, total):
        eta = (time.monotonic() - self.t0) / done * (total - done)
        print(f"[{done:>{len(str(total))}}/{total}] {_line(record)}  ETA {_clock(eta)}", file=self.stream, flush=True)


class RichObserver(runner.Observer):
    """A live progress bar (run i/n, renderer, ETA) with finished runs above it."""

    def __init__(self, total: int):
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )

        self.progress = Progress(
            TextColumn("run"),
            MofNCompleteColumn(),
            BarColumn(),
            TextColumn("{task.description}"),
            TimeElapsedColumn(),
            TextColumn("ETA"),
            TimeRemainingColumn(),
        )
        self.task = self.progress.add_task("", total=total)
        self.progress.start()

    def started(self, record, done, total):
        self.progress.update(self.task, description=f"{record.renderer}: {record.config} r{record.repetition}")

    def finished(self, record, done, total):
        style = "green" if record.status == RunStatus.OK else "red"
        text = _line(record)
        self.progress.console.print(f"[{style}]{text[:11]}[/]{text[11:]}", highlight=False)
        self.progress.update(self.task, completed=done)

    def close(self):
        self.progress.stop()


def _line(record: manifests.RunRecord) -> str:
    text = f"{record.status:<11} {record.config} r{record.repetition}  {record.seconds or 0:.2f} s"
    if record.status != RunStatus.OK and record.stderr_tail:
        text += f"  ({record.stderr_tail.splitlines()[-1][:160]})"
    return text


def _clock(seconds: float) -> str:
    s = round(seconds)
    return f"{s // 3600}:{s % 3600 // 60:02d}:{s % 60:02d}"


def mark_unavailable(manifest: manifests.Manifest, binary: Path, cwd: Path, out) -> None:
    """Probes each renderer once, and once more per value of an option its
    runs pass that a device may lack (configurations.probe_args: gpu_rt's
    --gpu-rt-reorder hit needs an extension of its own); the runs of a
    renderer, or of such a value, that the binary or the device cannot run
    are marked unavailable with the probe's reason instead of failing one by
    one."""
    probes: dict[tuple[str, tuple[str, ...]], str] = {}  # (renderer, options) -> the scene to probe on
    probe_of: dict[str, tuple[str, tuple[str, ...]]] = {}  # configuration id -> its probe
    for c in manifest.configs:
        key = (c["renderer"], configurations.probe_args(c))
        probes.setdefault(key, c["scene_path"])
        probe_of[c["id"]] = key
    failed = {}
    for (renderer, args), scene in probes.items():
        reason = runner.probe_renderer(binary, renderer, scene, cwd, args=args)
        if reason is None:
            continue
        failed[(renderer, args)] = reason
        what = " ".join([renderer, *args])
        print(f"bench: skipping {what}: {reason.splitlines()[-1] if reason else ''}", file=out)
    for r in manifest.runs:
        reason = failed.get(probe_of.get(r.config, (r.renderer, ())))
        if reason is not None:
            r.status, r.stderr_tail = RunStatus.UNAVAILABLE, reason


def machine_warnings() -> list[str]:
    cores = os.cpu_count() or 1
    return noise.governor_warnings(noise.read_governors()) + noise.load_warnings(noise.read_load_average(), cores)


def spread_warnings(run_dir: Path) -> list[str]:
    """After the runs: configurations whose repetitions disagree."""
    from rtbench import load, stats

    try:
        summary = stats.summarize_configs(load.load_runs([run_dir]))
    except load.RunDataError as e:
        return [f"could not check the spread between repetitions: {e}"]
    spreads = {stats.config_label(r): r["rep_spread"] for _, r in summary.iterrows()}
    return noise.spread_warnings(spreads)


def run_report(run_dir: Path, report_dir: Path) -> int:
    """The report of the run, in this process: the report command as
    scripts/report.py runs it (this Python has its packages: the bench needs
    them too). Its exit status; a report that fails, even by an exception,
    says so and how to make it again, and leaves the run directory as it is."""
    from rtbench import cli

    try:
        status = cli.run("report", [str(run_dir), "-o", str(report_dir)])
    except KeyboardInterrupt:
        print(
            f"bench: the report was interrupted; the runs are kept in {run_dir}.\n"
            f"bench: report them with: scripts/report.py {run_dir}",
            file=sys.stderr,
        )
        return 130
    except SystemExit as e:  # argparse's way out; sys.exit() and sys.exit(None) mean success
        status = 0 if e.code is None else e.code if isinstance(e.code, int) else 1
    except Exception:  # a bug in the report: its traceback, then the way to retry
        traceback.print_exc()
        status = 1
    if status != 0:
        print(
            f"bench: the report failed (exit status {status}); the runs are kept in {run_dir}.\n"
            f"bench: report them with: scripts/report.py {run_dir}",
            file=sys.stderr,
        )
    return status


def main(argv: list[str] | None = None, prog: str = "bench") -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    args = parse_args(argv, prog)
    args.command_line = [prog, *argv]
    if args.resume:
        return resume_run(args)
    try:
        profile, configs, order = plan(args)
    except ProfileError as e:
        print(f"bench: {e}", file=sys.stderr)
        return 2
    if args.dry_run:
        for i, (rep, c) in enumerate(order, 1):
            print(
                f"{i:4} r{rep} {c.id}: {' '.join(c.argv(Path('raytracer'), Path('X.csv'), Path('X.meta.json'))[1:-5])}"
            )
        return 0
    try:
        binary = resolve_binary(args, profile)
    except KeyboardInterrupt:
        print("bench: interrupted while building; no run directory was made", file=sys.stderr)
        return 130
    if binary is None:
        return 1
    return run_profile(args, profile, configs, order, binary)


def resolve_binary(args: argparse.Namespace, profile: profiles.Profile) -> Path | None:
    preset = args.preset or profile.preset
    given = args.binary or binary_from_environment(preset)
    if given:
        if not given.is_file():
            print(f"bench: binary {given}: no such file", file=sys.stderr)
            return None
        if reason := emulation.foreign_binary_reason(given):
            print(f"bench: {reason}", file=sys.stderr)
            return None
        return given.resolve()
    try:
        return builder.build(preset, names.REPO_ROOT, args.jobs, sys.stdout)
    except builder.BuildError as e:
        print(f"bench: {e}", file=sys.stderr)
        return None


def run_profile(args, profile, configs, order, binary: Path) -> int:
    """Runs the schedule into a new run directory and reports on it."""
    run_dir = manifests.make_run_dir(args.runs_dir, profile.name)
    with manifests.run_dir_lock(run_dir):
        configs, order = _place_scenes(configs, order, run_dir)
        manifest = manifests.Manifest.start(
            profile,
            configs,
            manifests.plan_runs(order, binary, run_dir),
            binary,
            args.command_line,
            manifests.host_info(),
            machine_warnings(),
        )
        for w in manifest.warnings:
            print(f"bench: warning: {w}", file=sys.stderr)
        print(
            f"bench: profile {profile.name}: {len(configs)} configurations x {len(order) // len(configs)} "
            f"repetitions = {len(order)} runs -> {run_dir}",
            flush=True,
        )
        manifests.write_manifest(run_dir, manifest)
        completed = run_manifest(args, manifest, run_dir, binary_to_probe=binary)
    return finish(args, manifest, run_dir, completed)


def resume_run(args: argparse.Namespace) -> int:
    """--resume RUN_DIR: runs the pending and interrupted runs of an
    unfinished run with the same binary and scenes, then reports."""
    run_dir = args.resume
    if not run_dir.is_dir():
        print(f"bench: --resume {run_dir}: not a directory", file=sys.stderr)
        return 2
    try:
        with manifests.run_dir_lock(run_dir):
            manifest = manifests.resume_manifest(run_dir, args.binary)
            _check_profile(args, manifest)
            missing = manifest.missing()
            kept = manifest.counts().get(RunStatus.OK, 0)
            print(
                f"bench: resuming {run_dir} (profile {manifest.profile.get('name')}): "
                f"{sum(map(len, missing.values()))} runs of {len(missing)} configurations to go, "
                f"{kept} finished runs kept",
                flush=True,
            )
            if manifest.host.get("logical_cores") != os.cpu_count():
                print(
                    f"bench: warning: this machine has {os.cpu_count()} logical cores, the run started on one "
                    f"with {manifest.host.get('logical_cores')}",
                    file=sys.stderr,
                )
            manifest.resumed.append({"at": manifests.utc_now(), "command_line": args.command_line})
            manifests.write_manifest(run_dir, manifest)
            completed = run_manifest(args, manifest, run_dir)
    except manifests.ResumeError as e:
        print(f"bench: cannot resume: {e}", file=sys.stderr)
        return 2
    except manifests.RunDirBusy as e:
        print(f"bench: {e}", file=sys.stderr)
        return 1
    return finish(args, manifest, run_dir, completed)


def _check_profile(args: argparse.Namespace, manifest: manifests.Manifest) -> None:
    """A --profile given with --resume must be the run's own, unchanged."""
    if not args.profile:
        return
    try:
        given = profiles.load_profile(args.profile)
    except ProfileError as e:
        raise manifests.ResumeError(str(e)) from None
    recorded = manifest.profile.get("definition")
    if given.name != manifest.profile.get("name") or json.loads(json.dumps(given.raw, default=str)) != recorded:
        raise manifests.ResumeError(
            f"{args.resume} ran profile {manifest.profile.get('name')!r} "
            f"({manifest.profile.get('path')}); {given.path} is not that profile as it was"
        )


def run_manifest(args, manifest: manifests.Manifest, run_dir: Path, binary_to_probe: Path | None = None) -> bool:
    """Runs the manifest's pending runs (first probing each renderer when a
    new run starts); False when SIGINT or SIGTERM stopped it, the manifest
    then marked interrupted by that signal."""
    try:
        with runner.interruptible():
            if binary_to_probe is not None:
                mark_unavailable(manifest, binary_to_probe, names.REPO_ROOT, sys.stderr)
            return _execute(args, manifest, run_dir, float(manifest.profile["timeout_s"]))
    except KeyboardInterrupt as e:
        if manifest.status == ManifestStatus.COMPLETE:  # the signal came after the last run
            return True
        manifests.mark_interrupted(run_dir, manifest, e)
        return False


def _place_scenes(configs, order, run_dir: Path):
    """The configurations and the schedule with the generated scenes written
    into the run directory (profiles.GENERATED_SCENES)."""
    placed = manifests.write_generated_scenes(configs, run_dir, sys.stdout)
    by_id = {c.id: c for c in placed}
    return placed, [(rep, by_id[c.id]) for rep, c in order]


def _execute(args, manifest: manifests.Manifest, run_dir: Path, timeout: float) -> bool:
    pending = sum(r.status == RunStatus.PENDING for r in manifest.runs)
    rich_ok = sys.stdout.isatty() and not args.plain and not os.environ.get("CI")
    observer = RichObserver(pending) if rich_ok and pending else PlainObserver()
    try:
        return runner.execute(manifest, run_dir, names.REPO_ROOT, timeout, observer)
    finally:
        if isinstance(observer, RichObserver):
            observer.close()


def finish(args, manifest: manifests.Manifest, run_dir: Path, completed: bool) -> int:
    """Warnings, the summary line, the report, the exit status."""
    counts = manifest.counts()
    if counts.get(RunStatus.OK):
        # Printed, not stored: the report recomputes them from the data.
        for w in spread_warnings(run_dir):
            print(f"bench: warning: {w}", file=sys.stderr)
    print(f"bench: {', '.join(f'{n} {k}' for k, n in sorted(counts.items()))} -> {run_dir}")
    if not completed:
        missing = manifest.missing()
        print(
            f"bench: interrupted by {manifest.interrupted_by}: the running configuration was stopped, "
            f"{counts.get(RunStatus.OK, 0)} finished runs kept, {sum(map(len, missing.values()))} runs of "
            f"{len(missing)} configurations missing.\n"
            f"bench: finish them with: scripts/bench --resume {run_dir}\n"
            f"bench: report what finished with: scripts/report.py {run_dir}",
            file=sys.stderr,
        )
        return 128 + signal.Signals[manifest.interrupted_by].value
    if counts.get(RunStatus.OK) and not args.no_report:
        status = run_report(run_dir, args.report_dir or run_dir / "report")
        if status != 0:
            return 130 if status == 130 else 1
    return 1 if counts.get(RunStatus.FAILED) or not counts.get(RunStatus.OK) else 0
