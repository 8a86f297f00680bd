"""Shared fixtures for the Python tests: the repository, its scripts, the binary."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

REPO_ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO_ROOT / "scripts"))


@pytest.fixture(scope="session")
def repo_root() -> Path:
    return REPO_ROOT


@pytest.fixture(scope="session")
def raytracer() -> Path:
    """The binary under test: $RT_BINARY, else the debug build, else the release build."""
    candidates = [
        os.environ.get("RT_BINARY"),
        REPO_ROOT / "build/debug/raytracer",
        REPO_ROOT / "build/release/raytracer",
    ]
    for c in candidates:
        if c and Path(c).is_file():
            return Path(c)
    pytest.fail("no raytracer binary: build a preset first or set RT_BINARY")


def has_tracy_client(binary: Path) -> bool:
    """Whether `binary --version` names a Tracy client version ("Tracy client: 0.14.1", not "not built in")."""
    done = subprocess.run([binary, "--version"], capture_output=True, text=True, timeout=60)
    return any(
        line.startswith("Tracy client: ") and line.split(": ", 1)[1][:1].isdigit() for line in done.stdout.splitlines()
    )


@pytest.fixture(scope="session")
def tracy_raytracer() -> Path:
    """A binary with the Tracy client built in: $RT_PROFILE_BINARY, else the
    profile preset's build (scripts/test builds it before pytest), else
    $RT_BINARY when that one has it (under Nix it is the profile preset's)."""
    candidates = [
        os.environ.get("RT_PROFILE_BINARY"),
        REPO_ROOT / "build/profile/raytracer",
        os.environ.get("RT_BINARY"),
    ]
    for c in candidates:
        if c and Path(c).is_file() and has_tracy_client(Path(c)):
            return Path(c)
    # scripts/test with RT_TEST_PRESETS leaving out the profile preset says so;
    # anywhere else a missing Tracy build is a failure, not a silent skip.
    if os.environ.get("RT_TEST_WITHOUT_PROFILE") == "1":
        pytest.skip("scripts/test ran without the profile preset (RT_TEST_PRESETS)")
    pytest.fail("no raytracer binary with the Tracy client: build the profile preset or set RT_PROFILE_BINARY")


@pytest.fixture
def tmpfs(tmp_path):
    """mount(name, size): a tmpfs of `size` at tmp_path/name, unmounted after
    the test; skips the test where mounting is not permitted (not root, or
    a container without CAP_SYS_ADMIN). The fault tests fill such a file
    system, or remount it read-only."""
    mounted = []

    def mount(name: str, size: str) -> Path:
        path = tmp_path / name
        path.mkdir()
        done = subprocess.run(
            ["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(path)], capture_output=True, text=True
        )
        if done.returncode != 0:
            pytest.skip(f"cannot mount a tmpfs here ({done.stderr.strip() or done.returncode}): the fault needs one")
        mounted.append(path)
        return path

    yield mount
    for path in reversed(mounted):
        subprocess.run(["umount", "-l", str(path)], check=False)
