"""Shared fixtures for the Python tests: the repository, its scripts, the binary."""

from __future__ import annotations

import os
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
    candidates = [os.environ.get("RT_BINARY"), REPO_ROOT / "build/debug/raytracer", REPO_ROOT / "build/release/raytracer"]
    for c in candidates:
        if c and Path(c).is_file():
            return Path(c)
    pytest.fail("no raytracer binary: build a preset first or set RT_BINARY")
