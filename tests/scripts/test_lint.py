"""scripts/lint holds files to the committed rules (.clang-format, ruff.toml),
whatever directory they lie in, and names the file and the rule it breaks.
Skipped where the tools are absent (scripts/test runs scripts/lint before
pytest, which installs ruff on Debian)."""

from __future__ import annotations

import shutil
import subprocess
import tomllib
from pathlib import Path

import pytest


def clang_format_major(repo_root: Path) -> str:
    """N of the clang-format-N that dependencies.toml installs: the version the rules are checked with."""
    package = tomllib.loads((repo_root / "dependencies.toml").read_text())["clang-format"]["debian13"]
    return package.rpartition("-")[2]


def has_clang_format(major: str) -> bool:
    for name in (f"clang-format-{major}", "clang-format"):
        path = shutil.which(name)
        if path and f" version {major}." in subprocess.run([path, "--version"], capture_output=True, text=True).stdout:
            return True
    return False


def has_ruff(repo_root: Path) -> bool:
    return (repo_root / "build/tools/ruff/bin/ruff").exists() or shutil.which("ruff") is not None


def lint(repo_root: Path, *files: Path) -> subprocess.CompletedProcess:
    return subprocess.run([str(repo_root / "scripts/lint"), *map(str, files)], capture_output=True, text=True)


def lint_text(repo_root: Path, path: Path, text: str) -> subprocess.CompletedProcess:
    path.write_text(text)
    return lint(repo_root, path)


@pytest.fixture
def cpp(repo_root):
    major = clang_format_major(repo_root)
    if not has_clang_format(major):
        pytest.skip(f"no clang-format {major} (scripts/setup-debian installs it)")
    return repo_root


@pytest.fixture
def python(repo_root):
    if not has_ruff(repo_root):
        pytest.skip("no ruff (scripts/lint installs it into build/tools/ruff)")
    return repo_root


def test_cpp_that_the_rules_would_change_fails_naming_the_file(cpp, tmp_path):
    source = tmp_path / "squeezed.cpp"
    source.write_text("int  twice( int x ){return 2*x;}\n")
    done = lint(cpp, source)
    assert done.returncode == 1
    assert f"{source}:1:" in done.stderr and "clang-format" in done.stderr


def test_cpp_as_the_rules_write_it_passes(cpp, tmp_path):
    done = lint_text(cpp, tmp_path / "formatted.cpp", "int twice(int x) { return 2 * x; }\n")
    assert done.returncode == 0, done.stderr


def test_the_column_limit_is_the_committed_one(cpp, tmp_path):
    """A call of 110 columns stays on one line: the repository's 120, not
    clang-format's default 80, is applied to a file outside the repository."""
    source = tmp_path / "wide.cpp"
    arguments = ", ".join(f"argument{i}" for i in range(7))
    line = f"int wide() {{ return combine({arguments}, 0); }}\n"
    assert 100 < len(line) < 120
    source.write_text(line)
    assert lint(cpp, source).returncode == 0


def test_python_that_ruff_format_would_change_fails_naming_the_file(python, tmp_path):
    source = tmp_path / "squeezed.py"
    source.write_text("x=[1,2 ,3]\n")
    done = lint(python, source)
    assert done.returncode == 1
    assert str(source) in done.stderr and "ruff.toml" in done.stderr


def test_python_that_breaks_a_lint_rule_fails_naming_the_rule(python, tmp_path):
    source = tmp_path / "unused.py"
    source.write_text("import os\n\nx = 1\n")
    done = lint(python, source)
    assert done.returncode == 1
    assert "F401" in done.stderr and str(source) in done.stderr


def test_clean_python_passes(python, tmp_path):
    done = lint_text(python, tmp_path / "clean.py", '"""A module the rules accept."""\n\nx = [1, 2, 3]\n')
    assert done.returncode == 0, done.stderr


def test_a_file_of_another_language_is_refused(repo_root, tmp_path):
    source = tmp_path / "notes.txt"
    source.write_text("text\n")
    done = lint(repo_root, source)
    assert done.returncode == 2 and "notes.txt" in done.stderr
