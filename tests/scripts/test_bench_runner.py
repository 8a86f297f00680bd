"""The bench runner end to end, with the raytracer fixture binary (no build):
the quick profile, a failing configuration, Ctrl-C, bad input."""

import json
import os
import signal
import subprocess
import sys
import textwrap
import time

import pytest

from rtbench import load, names

SMALL = ["--width", "32", "--height", "24"]


def bench(repo_root, raytracer, *args, **kw):
    env = {**os.environ, "RT_SKIP_SETUP": "1", "RT_PYTHON": sys.executable}
    return subprocess.run(
        [repo_root / "scripts/bench", "--binary", raytracer, "--plain", *map(str, args)],
        capture_output=True,
        text=True,
        env=env,
        **kw,
    )


def only_run_dir(runs_dir):
    (run_dir,) = list(runs_dir.iterdir())
    return run_dir


def write_profile(tmp_path, body):
    path = tmp_path / "p.toml"
    path.write_text(textwrap.dedent(body))
    return path


def test_quick_profile_produces_a_complete_run_directory(repo_root, raytracer, tmp_path):
    done = bench(repo_root, raytracer, "--profile", "quick", "--runs-dir", tmp_path, *SMALL)
    assert done.returncode == 0, done.stdout + done.stderr
    run_dir = only_run_dir(tmp_path)
    assert run_dir.name.endswith("-quick")
    manifest = json.loads((run_dir / "manifest.json").read_text())
    assert manifest["status"] == "complete" and manifest["finished_at"]
    assert len(manifest["configs"]) == 2 * 2 * len(names.RENDERERS)  # scenes x stages x renderers
    assert len(manifest["runs"]) == 2 * len(manifest["configs"])  # 2 repetitions
    assert {r["status"] for r in manifest["runs"]} <= {"ok", "unavailable"}
    reference_runs = [r for r in manifest["runs"] if r["renderer"] == names.reference_renderer()]
    assert reference_runs and all(r["status"] == "ok" and r["exit_code"] == 0 for r in reference_runs)
    for r in manifest["runs"]:
        if r["status"] == "ok":
            assert (run_dir / r["csv"]).is_file() and (run_dir / r["meta"]).is_file()
            assert "--width" in r["argv"] and "32" in r["argv"]
        else:
            assert r["stderr_tail"], "an unavailable renderer says why"
    # Renderers interleave: the first runs of a round cycle through them.
    assert [r["renderer"] for r in manifest["runs"][: len(names.RENDERERS)]] == names.RENDERERS
    assert [r["repetition"] for r in manifest["runs"]][-1] == 1
    frames = load.load_runs([run_dir])
    assert set(frames[names.WIDTH]) == {32}
    assert (run_dir / "report/README.md").is_file() and (run_dir / "report/tables/table4-optimized.md").is_file()
    assert not [p for p in run_dir.rglob("*") if ".tmp" in p.name]


def test_failing_configuration_is_reported_and_the_others_still_run(repo_root, raytracer, tmp_path):
    profile = write_profile(
        tmp_path,
        """
        description = "one scene breaks"
        scenes = ["default", "random20"]
        stages = ["optimized"]
        width = 16
        height = 8
        frames = 2
        repetitions = 2
        [renderers.sequential]
        [[overrides]]
        scenes = ["random20"]
        args = ["--no-such-option"]
    """,
    )
    runs = tmp_path / "runs"
    done = bench(repo_root, raytracer, "--profile", profile, "--runs-dir", runs, "--no-report")
    assert done.returncode == 1
    run_dir = only_run_dir(runs)
    manifest = json.loads((run_dir / "manifest.json").read_text())
    by_scene = {}
    for r in manifest["runs"]:
        by_scene.setdefault(r["config"].split("-")[0], []).append(r)
    assert [r["status"] for r in by_scene["default"]] == ["ok", "ok"]
    assert [(r["status"], r["exit_code"]) for r in by_scene["random20"]] == [("failed", 2), ("failed", 2)]
    assert "no-such-option" in by_scene["random20"][0]["stderr_tail"]
    assert "failed" in done.stdout and "2 failed, 2 ok" in done.stdout
    assert not (run_dir / "report").exists()


def test_ctrl_c_keeps_finished_runs_and_writes_the_manifest(repo_root, raytracer, tmp_path):
    profile = write_profile(
        tmp_path,
        """
        description = "many short runs"
        scenes = ["random20"]
        stages = ["original"]
        width = 64
        height = 48
        warmup = 0
        frames = 2
        repetitions = 200
        [renderers.sequential]
    """,
    )
    runs = tmp_path / "runs"
    env = {**os.environ, "RT_SKIP_SETUP": "1", "RT_PYTHON": sys.executable}
    proc = subprocess.Popen(
        [repo_root / "scripts/bench", "--binary", raytracer, "--plain", "--profile", profile, "--runs-dir", runs],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
    )
    manifest_path = None
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        found = list(runs.glob("*/manifest.json")) if runs.is_dir() else []
        if found and json.loads(found[0].read_text())["counts"].get("ok", 0) >= 2:
            manifest_path = found[0]
            break
        time.sleep(0.05)
    assert manifest_path, "the runner never finished two runs"
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    manifest = json.loads(manifest_path.read_text())
    assert manifest["status"] == "interrupted"
    statuses = [r["status"] for r in manifest["runs"]]
    finished = statuses.count("ok")
    assert finished >= 2 and statuses.count("pending") > 0
    assert set(statuses) <= {"ok", "interrupted", "pending"} and statuses.count("interrupted") <= 1
    assert statuses[:finished] == ["ok"] * finished
    run_dir = manifest_path.parent
    assert len(load.load_runs([run_dir])[names.RUN_ID].unique()) == finished
    assert not [p for p in run_dir.rglob("*") if ".tmp" in p.name]
    assert "interrupted" in err and "scripts/report.py" in err


@pytest.mark.parametrize(
    "args, message",
    [
        (["nosuchscene"], "no scene 'nosuchscene'"),
        (["--profile", "nosuchprofile"], "no profile 'nosuchprofile'"),
    ],
)
def test_bad_scene_or_profile_exits_2(repo_root, raytracer, tmp_path, args, message):
    done = bench(repo_root, raytracer, *args, "--runs-dir", tmp_path)
    assert done.returncode == 2 and message in done.stderr
    assert list(tmp_path.iterdir()) == []


def test_dry_run_lists_the_schedule_without_running(repo_root, raytracer, tmp_path):
    done = bench(repo_root, raytracer, "random100", "--dry-run", "--runs-dir", tmp_path)
    assert done.returncode == 0
    lines = done.stdout.splitlines()
    assert all("random100" in line for line in lines) and "--stage original" in lines[0]
    assert len(lines) > len(names.RENDERERS) * len(names.STAGES)  # paper: repetitions too
    assert list(tmp_path.iterdir()) == []


def test_generated_scene_and_accels_are_run_and_recorded(repo_root, raytracer, tmp_path):
    """A scene the generator makes is written into the run directory; each
    accel of the profile runs as --accel and comes back in the CSV, the
    sphere count in the tidy frame."""
    profile = write_profile(
        tmp_path,
        f"""
        description = "generated scene x accels"
        scenes = ["random3"]
        stages = ["optimized"]
        accels = {list(names.RUN_ACCELS)!r}
        width = 16
        height = 8
        warmup = 0
        frames = 1
        [renderers.sequential]
    """.replace("'", '"'),
    )
    runs = tmp_path / "runs"
    done = bench(repo_root, raytracer, "--profile", profile, "--runs-dir", runs, "--no-report")
    assert done.returncode == 0, done.stdout + done.stderr
    run_dir = only_run_dir(runs)
    scene = run_dir / "scenes/random3.json"
    assert len(json.loads(scene.read_text())["spheres"]) == 3
    manifest = json.loads((run_dir / "manifest.json").read_text())
    assert {c["scene_path"] for c in manifest["configs"]} == {str(scene)}
    frames = load.load_runs([run_dir])
    assert sorted(set(frames[names.ACCEL])) == sorted(names.RUN_ACCELS)
    assert set(frames[names.SPHERES]) == {3}
