"""One way in: `python3 -m rtbench bench|report|compare|gen-scene`, and the commands
of scripts/ as thin wrappers of it, each with its options and exit codes."""

import os
import subprocess
import sys

import pytest

WRAPPERS = {"bench": "scripts/bench", "report": "scripts/report.py", "compare": "scripts/compare.py",
            "gen-scene": "scripts/gen_scene.py"}


def run(repo_root, *argv):
    env = {**os.environ, "PYTHONPATH": str(repo_root / "scripts"), "RT_SKIP_SETUP": "1", "RT_PYTHON": sys.executable}
    return subprocess.run([*map(str, argv)], capture_output=True, text=True, env=env, cwd=repo_root)


@pytest.mark.parametrize("command", WRAPPERS)
def test_every_wrapper_prints_its_help(repo_root, command):
    done = run(repo_root, repo_root / WRAPPERS[command], "--help")
    assert done.returncode == 0 and "--help" in done.stdout, done.stderr


def test_a_wrapper_is_the_package_command(repo_root):
    """gen-scene, the command that needs no pandas (the cheapest to start)."""
    wrapper = run(repo_root, repo_root / WRAPPERS["gen-scene"], "--help")
    assert wrapper.stdout == run(repo_root, sys.executable, "-m", "rtbench", "gen-scene", "--help").stdout


def test_the_package_lists_its_commands_and_rejects_others(repo_root):
    listed = run(repo_root, sys.executable, "-m", "rtbench", "--help")
    assert listed.returncode == 0 and all(c in listed.stdout for c in WRAPPERS)
    unknown = run(repo_root, sys.executable, "-m", "rtbench", "frobnicate")
    assert unknown.returncode == 2 and "unknown command 'frobnicate'" in unknown.stderr


def test_no_script_edits_sys_path(repo_root):
    scripts = [p for p in (repo_root / "scripts").rglob("*") if p.is_file() and "__pycache__" not in p.parts]
    assert [p for p in scripts if "sys.path.insert" in p.read_text(errors="replace")] == []
