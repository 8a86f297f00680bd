"""The bench runner under interruption, with real processes and real signals:
SIGTERM or SIGINT while a configuration runs kills that configuration's
process, keeps the finished ones and a manifest that says what is missing;
the report covers what finished and names what is missing; --resume runs the
rest. Two runners never share a run directory.

To make "while a configuration runs" certain whatever the binary's speed,
the test stops (SIGSTOP) the raytracer process of a later run before it
signals the runner: that run cannot finish on its own, and only the runner
can end it (SIGKILL ends a stopped process too)."""

import json
import os
import shutil
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from rtbench import load

PROFILE = """
    description = "three short runs of one configuration"
    scenes = ["random20"]
    stages = ["original"]
    width = 16
    height = 12
    warmup = 0
    frames = 3
    repetitions = 3
    [renderers.sequential]
"""


def environment():
    return {**os.environ, "RT_SKIP_SETUP": "1", "RT_PYTHON": sys.executable}


def start_bench(repo_root, *args):
    return subprocess.Popen(
        [repo_root / "scripts/bench", "--plain", *map(str, args)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=environment(),
    )


def bench(repo_root, *args):
    return subprocess.run(
        [repo_root / "scripts/bench", "--plain", *map(str, args)],
        capture_output=True,
        text=True,
        env=environment(),
        timeout=300,
    )


def write_profile(tmp_path):
    path = tmp_path / "p.toml"
    path.write_text(textwrap.dedent(PROFILE))
    return path


def raytracers_writing_into(run_dir: Path) -> list[int]:
    """Pids of the live raytracer processes whose output goes into run_dir."""
    pids = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            argv = (entry / "cmdline").read_bytes().split(b"\0")
            state = (entry / "stat").read_text().rsplit(")", 1)[1].split()[0]
        except OSError:
            continue
        if b"--csv" in argv and any(str(run_dir).encode() in a for a in argv) and state != "Z":
            pids.append(int(entry.name))
    return pids


def wait_for(predicate, what, timeout=120):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(0.02)
    pytest.fail(f"timed out waiting for {what}")


def manifest_of(run_dir: Path) -> dict:
    return json.loads((run_dir / "manifest.json").read_text())


def one_run_dir(runs: Path) -> Path:
    return wait_for(lambda: next(iter(runs.glob("*/manifest.json")), None), "a manifest").parent


def stop_a_later_run(run_dir: Path) -> int:
    """Waits until one run finished, then SIGSTOPs the raytracer of a later
    one and returns its pid."""
    wait_for(lambda: manifest_of(run_dir)["counts"].get("ok", 0) >= 1, "the first run to finish")
    while True:
        pid = wait_for(lambda: raytracers_writing_into(run_dir), "a raytracer of the second run")[0]
        try:
            os.kill(pid, signal.SIGSTOP)
        except ProcessLookupError:
            continue  # it finished in between: take the next
        state = wait_for(lambda pid=pid: _state(pid), "the stop to take effect")
        if state == "T":
            return pid
        assert state == "Z", state  # finished just before the stop: take the next


def _state(pid: int) -> str | None:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return "Z"
    return state if state in ("T", "Z", "X") else None


def interrupt(repo_root, raytracer, tmp_path, signum):
    """Starts a run, signals the runner while a later configuration runs;
    (the runner's result, its run directory, the stopped raytracer's pid)."""
    runs = tmp_path / "runs"
    proc = start_bench(
        repo_root, "--binary", raytracer, "--profile", write_profile(tmp_path), "--runs-dir", runs, "--no-report"
    )
    try:
        run_dir = one_run_dir(runs)
        victim = stop_a_later_run(run_dir)
        proc.send_signal(signum)
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    return subprocess.CompletedProcess(proc.args, proc.returncode, out, err), run_dir, victim


def test_sigterm_stops_the_running_configuration_report_names_the_rest_and_resume_completes(
    repo_root, raytracer, tmp_path
):
    done, run_dir, victim = interrupt(repo_root, raytracer, tmp_path, signal.SIGTERM)
    assert done.returncode == 143, done.stderr
    wait_for(lambda: not Path(f"/proc/{victim}").exists(), "the running configuration's process to be gone", timeout=10)
    assert raytracers_writing_into(run_dir) == []
    manifest = manifest_of(run_dir)
    assert manifest["status"] == "interrupted" and manifest["interrupted_by"] == "SIGTERM"
    statuses = [r["status"] for r in manifest["runs"]]
    finished = statuses.count("ok")
    assert 1 <= finished <= 2 and statuses[:finished] == ["ok"] * finished
    assert statuses[finished] == "interrupted" and set(statuses[finished + 1 :]) <= {"pending"}
    config = manifest["runs"][0]["config"]
    assert manifest["missing"] == {config: list(range(finished, 3))}
    interrupted = manifest["runs"][finished]
    assert interrupted["exit_code"] is None
    assert not (run_dir / interrupted["csv"]).exists() and not (run_dir / interrupted["meta"]).exists()
    assert not [p for p in run_dir.rglob("*") if ".tmp" in p.name]
    assert f"scripts/bench --resume {run_dir}" in done.stderr and "SIGTERM" in done.stderr

    # The report of the unfinished run: the finished runs, and what is missing, on the console and in the README.
    report = subprocess.run(
        [repo_root / "scripts/report.py", run_dir, "-o", tmp_path / "report"],
        capture_output=True,
        text=True,
        env=environment(),
        timeout=300,
    )
    assert report.returncode == 0, report.stderr
    assert f"run {run_dir.name} is unfinished (interrupted by SIGTERM)" in report.stderr
    assert f"{config} ({finished} of 3 repetitions)" in report.stderr
    readme = (tmp_path / "report/README.md").read_text()
    assert f"{config} {' '.join(f'r{r}' for r in range(finished, 3))} | missing" in readme
    assert f"scripts/bench --resume {run_dir}" in readme
    summary = (tmp_path / "report/data/summary.csv").read_text()
    assert config.split("-")[0] in summary

    resumed = bench(repo_root, "--resume", run_dir, "--no-report")
    assert resumed.returncode == 0, resumed.stdout + resumed.stderr
    assert f"{3 - finished} runs of 1 configurations to go, {finished} finished runs kept" in resumed.stdout
    manifest = manifest_of(run_dir)
    assert manifest["status"] == "complete" and manifest["missing"] == {} and manifest["interrupted_by"] is None
    assert [r["status"] for r in manifest["runs"]] == ["ok"] * 3 and len(manifest["resumed"]) == 1
    frames = load.load_runs([run_dir])
    assert sorted(frames.drop_duplicates("run_id")["repetition"]) == [0, 1, 2]


def test_sigint_marks_the_run_interrupted_by_sigint(repo_root, raytracer, tmp_path):
    done, run_dir, victim = interrupt(repo_root, raytracer, tmp_path, signal.SIGINT)
    assert done.returncode == 130, done.stderr
    wait_for(lambda: not Path(f"/proc/{victim}").exists(), "the running configuration's process to be gone", timeout=10)
    manifest = manifest_of(run_dir)
    assert manifest["status"] == "interrupted" and manifest["interrupted_by"] == "SIGINT"
    assert "Traceback" not in done.stderr


def test_resume_refuses_another_build_a_changed_plan_and_a_finished_run(repo_root, raytracer, tmp_path):
    done, run_dir, _ = interrupt(repo_root, raytracer, tmp_path, signal.SIGTERM)
    assert done.returncode == 143
    before = (run_dir / "manifest.json").read_text()
    other_build = tmp_path / "raytracer-other"
    shutil.copy(raytracer, other_build)
    with open(other_build, "ab") as f:
        f.write(b"\0")
    refused = bench(repo_root, "--resume", run_dir, "--binary", other_build)
    assert refused.returncode == 2
    assert "cannot resume" in refused.stderr and "not the build this run started with" in refused.stderr
    changed = bench(repo_root, "--resume", run_dir, "--width", "64")
    assert changed.returncode == 2 and "cannot be changed with --width" in changed.stderr
    other_profile = bench(repo_root, "--resume", run_dir, "--profile", "quick")
    assert other_profile.returncode == 2 and "is not that profile" in other_profile.stderr
    assert (run_dir / "manifest.json").read_text() == before, "a refused resume changes nothing"

    assert bench(repo_root, "--resume", run_dir, "--no-report").returncode == 0
    again = bench(repo_root, "--resume", run_dir)
    assert again.returncode == 2 and "nothing to resume" in again.stderr


def test_two_runners_never_share_a_run_directory(repo_root, raytracer, tmp_path):
    """Two runs started together get two directories; a resume of a
    directory a runner is working in is refused while it works."""
    runs = tmp_path / "runs"
    profile = write_profile(tmp_path)
    args = ("--binary", raytracer, "--profile", profile, "--runs-dir", runs, "--no-report")
    first, second = start_bench(repo_root, *args), start_bench(repo_root, *args)
    try:
        for proc in (first, second):
            proc.communicate(timeout=300)
            assert proc.returncode == 0
    finally:
        for proc in (first, second):
            if proc.poll() is None:
                proc.kill()
    run_dirs = sorted(p.parent for p in runs.glob("*/manifest.json"))
    assert len(run_dirs) == 2
    for run_dir in run_dirs:
        manifest = manifest_of(run_dir)
        assert manifest["status"] == "complete" and len(manifest["runs"]) == 3
        assert {Path(a).parent.parent for r in manifest["runs"] for a in r["argv"] if a.endswith(".csv")} == {run_dir}

    busy_runs = tmp_path / "busy"
    proc = start_bench(repo_root, "--binary", raytracer, "--profile", profile, "--runs-dir", busy_runs, "--no-report")
    try:
        run_dir = one_run_dir(busy_runs)
        stop_a_later_run(run_dir)
        refused = bench(repo_root, "--resume", run_dir)
        assert refused.returncode == 1
        assert f"in use by another bench process (pid {proc.pid})" in refused.stderr
        proc.send_signal(signal.SIGTERM)
        proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 143
    assert bench(repo_root, "--resume", run_dir, "--no-report").returncode == 0


def test_a_signal_while_the_child_is_starting_still_kills_and_reaps_it(monkeypatch):
    """The window the end-to-end tests above only hit by chance: the child has
    exec'd but Popen has not returned it yet when the signal comes. The
    signal is raised from inside Popen here, as the runner's handler would
    see it; the child must still be killed and reaped, not left running."""
    from rtbench import runner

    started = []
    real_popen = subprocess.Popen

    def popen_then_signal(*args, **kwargs):
        proc = real_popen(*args, **kwargs)
        started.append(proc.pid)
        signal.raise_signal(signal.SIGINT)
        return proc

    monkeypatch.setattr(runner.subprocess, "Popen", popen_then_signal)
    try:
        with pytest.raises(runner.Interrupted), runner.interruptible():
            runner.run_process(["sleep", "60"], Path.cwd(), timeout=60)
        (pid,) = started
        assert not Path(f"/proc/{pid}").exists(), "the child was left running"
    finally:
        for pid in started:
            if Path(f"/proc/{pid}").exists():
                os.kill(pid, signal.SIGKILL)
                os.waitpid(pid, 0)
