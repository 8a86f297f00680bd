"""dependencies.toml is the project's one list of dependencies: every module
the Python code imports and every package CMake looks for is on it, the
shell's reading of it (scripts/setup-debian, which runs before Python is
installed) is a TOML parser's, and flake.nix takes its packages from it
rather than naming its own."""

from __future__ import annotations

import ast
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11 has no TOML parser; Debian 12 has 3.11
    tomllib = None

pytestmark = pytest.mark.skipif(tomllib is None, reason="Python < 3.11 has no tomllib")

ROLES = {
    "compiler",
    "build",
    "library",
    "test-library",
    "runtime",
    "check",
    "check-dlopen",
    "python",
    "python-interpreter",
    "develop",
    "lint",
    "cross",
}
RELEASES = ("debian12", "debian13")
# The restricted TOML that scripts/setup-debian's awk reads (dependencies.toml's header).
LINE = re.compile(r'^(#.*|\[[a-z0-9-]+\]|[a-z0-9]+ = "[^"\\]*"|)$')
# What CMake looks for, by the project's macros and by plain find_package.
CMAKE_LOOKUPS = (
    re.compile(r"\brt_require_package\((\w+)"),
    re.compile(r"\brt_require_pkg_config\(\w+ ([\w-]+)"),
    re.compile(r"\brt_require_program\(\w+ ([\w-]+)"),
    re.compile(r"\brt_optional_feature\(\w+ (\w+)"),
    re.compile(r"\bfind_package\((\w+)"),
)


@pytest.fixture(scope="module")
def deps(repo_root: Path) -> dict[str, dict[str, str]]:
    return tomllib.loads((repo_root / "dependencies.toml").read_text())


def words(value: str) -> list[str]:
    return value.split()


def values_of(deps, key: str) -> set[str]:
    return {w for dep in deps.values() for w in words(dep.get(key, ""))}


def test_the_file_keeps_the_format_the_shell_reads(repo_root):
    bad = [
        (n, line)
        for n, line in enumerate((repo_root / "dependencies.toml").read_text().splitlines(), 1)
        if not LINE.match(line)
    ]
    assert bad == [], 'one `key = "value"` per line, no escapes, no inline tables or arrays'


def test_every_entry_says_what_it_is_on_every_platform(deps):
    for name, dep in deps.items():
        assert dep.get("role") in ROLES, name
        for key in (*RELEASES, "nix"):
            assert isinstance(dep.get(key), str), f'{name}: `{key}` missing ("" for none)'
        if not all(dep[key] for key in (*RELEASES, "nix")):
            assert dep.get("why"), f"{name}: absent on a platform without a `why`"
        if dep["role"] == "python":
            assert dep.get("import"), f"{name}: a Python package names its import"


@pytest.mark.parametrize("release", RELEASES)
def test_setup_debian_reads_the_same_packages_as_a_toml_parser(repo_root, deps, release):
    listed = subprocess.run(
        [str(repo_root / "scripts/setup-debian"), "--list"],
        capture_output=True,
        text=True,
        env=dict(os.environ, RT_DEBIAN_RELEASE=release.removeprefix("debian")),
        check=True,
    )
    expected = list(dict.fromkeys(w for dep in deps.values() if dep["role"] != "cross" for w in words(dep[release])))
    assert listed.stdout.split() == expected


@pytest.mark.parametrize("release", RELEASES)
def test_setup_debian_lists_the_cross_build_as_a_toml_parser_reads_it(repo_root, deps, release):
    """--cross aarch64: the cross compiler and emulator (role cross), then the
    arm64 build of every entry marked cross = "arm64", from its
    arm64debian<N> where it names other packages."""
    listed = subprocess.run(
        [str(repo_root / "scripts/setup-debian"), "--cross", "aarch64", "--list"],
        capture_output=True,
        text=True,
        env=dict(os.environ, RT_DEBIAN_RELEASE=release.removeprefix("debian")),
        check=True,
    )
    expected = []
    for dep in deps.values():
        if dep["role"] == "cross":
            expected += words(dep[release])
        elif dep.get("cross") == "arm64":
            expected += [f"{w}:arm64" for w in words(dep.get(f"arm64{release}") or dep[release])]
    assert listed.stdout.split() == list(dict.fromkeys(expected))
    assert "qemu-user" in expected and "libhwy-dev:arm64" in expected
    assert all(dep.get("cross") in (None, "arm64") for dep in deps.values())


def test_setup_debian_refuses_a_cross_target_it_has_no_toolchain_for(repo_root):
    done = subprocess.run(
        [str(repo_root / "scripts/setup-debian"), "--cross", "riscv64", "--list"], capture_output=True, text=True
    )
    assert done.returncode != 0 and "--cross takes aarch64" in done.stderr and not done.stdout


def test_setup_debian_refuses_a_release_it_has_no_column_for(repo_root):
    done = subprocess.run(
        [str(repo_root / "scripts/setup-debian"), "--list"],
        capture_output=True,
        text=True,
        env=dict(os.environ, RT_DEBIAN_RELEASE="11"),
    )
    assert done.returncode != 0 and "debian11" in done.stderr and not done.stdout


def python_files(repo_root: Path):
    for top in ("scripts", "tests"):
        for path in sorted((repo_root / top).rglob("*.py")):
            if "build" not in path.relative_to(repo_root).parts:
                yield path


def local_modules(repo_root: Path) -> set[str]:
    """Modules of the project itself: files and packages under scripts/ and tests/."""
    names = {p.stem for p in python_files(repo_root)}
    names |= {p.parent.name for p in python_files(repo_root) if p.name == "__init__.py"}
    return names


def imported_modules(path: Path) -> set[str]:
    found = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            found |= {alias.name.partition(".")[0] for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found.add(node.module.partition(".")[0])
    return found


def test_every_module_the_python_code_imports_is_listed(repo_root, deps):
    local = local_modules(repo_root)
    listed = values_of(deps, "import")
    unlisted = {}
    for path in python_files(repo_root):
        for module in imported_modules(path) - set(sys.stdlib_module_names) - local - listed:
            unlisted.setdefault(module, path.relative_to(repo_root).as_posix())
    assert unlisted == {}, "add these to dependencies.toml (module: first file importing it)"


def test_the_import_scan_sees_third_party_modules(repo_root):
    """The scan itself can fail: pandas, imported by the report, is found."""
    assert "pandas" in set().union(*(imported_modules(p) for p in python_files(repo_root)))


def cmake_lookups(repo_root: Path) -> dict[str, str]:
    """Name -> file, of everything the CMake files look for (macro bodies,
    whose names are variables, are skipped)."""
    found = {}
    files = [
        repo_root / "CMakeLists.txt",
        *sorted((repo_root / "cmake").glob("*.cmake")),
        *sorted(p for top in ("src", "tests") for p in (repo_root / top).rglob("CMakeLists.txt")),
    ]
    for path in files:
        for pattern in CMAKE_LOOKUPS:
            for name in pattern.findall(path.read_text()):
                found.setdefault(name, path.relative_to(repo_root).as_posix())
    return found


def test_every_package_cmake_looks_for_is_listed(repo_root, deps):
    lookups = cmake_lookups(repo_root)
    assert {"TBB", "hwy", "Vulkan", "embree", "glslangValidator", "stb"} <= set(lookups), "the scan finds them"
    unlisted = {name: where for name, where in lookups.items() if name not in values_of(deps, "cmake")}
    assert unlisted == {}, "add these to dependencies.toml's `cmake` names"


def test_flake_nix_takes_its_packages_from_the_list(repo_root, deps):
    """flake.nix names no package of nixpkgs itself (only builders and lib),
    and every nixpkgs attribute of the list is a name Nix can read."""
    flake = (repo_root / "flake.nix").read_text()
    assert "builtins.fromTOML (builtins.readFile ./dependencies.toml)" in flake
    builders = {"legacyPackages", "writeShellApplication", "runCommand", "mkShell"}
    named = set(re.findall(r"\bpkgs\.([\w-]+)", flake)) - builders
    assert named == set(), f"flake.nix names packages the list should: {sorted(named)}"
    for name, dep in deps.items():
        assert all(re.fullmatch(r"[A-Za-z_][\w-]*(\.[A-Za-z_][\w-]*)*", attr) for attr in words(dep["nix"])), name
