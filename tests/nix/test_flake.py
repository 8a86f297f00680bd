"""Offline checks of flake.nix: it parses, pins nixpkgs by revision, and, with
nixpkgs replaced by the stub in tests/nix/stub-nixpkgs, evaluates to the
expected outputs for both systems (apps, packages, dev shell, checks and the
variables they set).

This checks the flake's shape, not a build: real nixpkgs cannot be
downloaded here, so no compiler or library of the pin is ever fetched.

Needs `nix` (Debian: nix-bin, which scripts/setup-debian installs); skipped
without it. Nix runs on a copy of the repository's files in a temporary git
repository, with a private store in a temporary directory, so it needs
neither root nor /nix, and writes nothing into the checkout (no flake.lock).
"""

from __future__ import annotations

import json
import os
import shlex
import shutil
import subprocess
from pathlib import Path

import pytest

NIXPKGS_REV = "8fd9daa3db09ced9700431c5b7ad0e8ba199b575"  # nixos-25.11, 2026-05-10
NIXPKGS_NAR_HASH = "sha256-Ti+ZBvW6yrWWAg2szExVTwCd4qOJ3KlVr1tFHfyfi8Q="
SYSTEMS = {"x86_64-linux": "x86_64", "aarch64-linux": "aarch64"}  # system -> lavapipe ICD arch
APPS = {"default": "raytracer", "bench": "raytracer-bench", "report": "raytracer-report"}
CHECKS = {"raytracer", "scripts-syntax", "app-default", "app-bench", "app-report"}
STUB = Path("tests/nix/stub-nixpkgs")

pytestmark = pytest.mark.skipif(
    shutil.which("nix") is None or shutil.which("nix-instantiate") is None,
    reason="nix is not installed (Debian: apt-get install nix-bin, or run scripts/setup-debian)",
)


class Nix:
    """Runs Nix 2.8+ against a private store, with flakes enabled."""

    def __init__(self, tmp: Path):
        self.store = tmp / "store"
        self.env = dict(os.environ, HOME=str(tmp / "home"), XDG_CACHE_HOME=str(tmp / "cache"))
        self.common = ["--store", str(self.store), "--option", "build-users-group", ""]

    def _run(self, argv: list[str], cwd: Path | None = None) -> str:
        done = subprocess.run(argv, capture_output=True, text=True, env=self.env, cwd=cwd, timeout=120)
        if done.returncode != 0:
            pytest.fail(f"{shlex.join(argv)} failed (exit {done.returncode}):\n{done.stderr}")
        return done.stdout

    def instantiate(self, *args: str) -> str:
        return self._run(["nix-instantiate", *self.common, *args])

    def nix(self, *args: str) -> str:
        return self._run(["nix", "--extra-experimental-features", "nix-command flakes", *self.common, *args])


@pytest.fixture(scope="module")
def nix(tmp_path_factory) -> Nix:
    return Nix(tmp_path_factory.mktemp("nix"))


@pytest.fixture(scope="module")
def flake(repo_root: Path, tmp_path_factory) -> Path:
    """The repository's files (tracked, or new and not ignored) as committed in a fresh git repository:
    flakes only see what git tracks, and this works the same in a CI clone and in a worktree."""
    listed = subprocess.run(
        ["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
        cwd=repo_root,
        capture_output=True,
        check=False,
    )
    if listed.returncode != 0:
        pytest.skip(f"not a git checkout, and flakes see only what git tracks: {listed.stderr.decode().strip()}")
    dest = tmp_path_factory.mktemp("flake")
    for name in filter(None, listed.stdout.decode().split("\0")):
        src = repo_root / name
        if src.is_file():  # deleted files are still listed until committed
            (dest / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / name)
    git = ["git", "-c", "user.name=test_flake", "-c", "user.email=test_flake@localhost", "-c", "commit.gpgsign=false"]
    for argv in (["init", "-q"], ["add", "-A"], ["commit", "-q", "-m", "flake under test"]):
        subprocess.run([*git, *argv], cwd=dest, check=True, capture_output=True)
    return dest


def flake_args(flake: Path) -> list[str]:
    return ["--offline", "--no-write-lock-file", "--override-input", "nixpkgs", f"path:{flake / STUB}"]


def evaluate(nix: Nix, flake: Path, output: str, apply: str):
    return json.loads(nix.nix("eval", "--json", *flake_args(flake), f"git+file://{flake}#{output}", "--apply", apply))


def shell_exports(script: str) -> dict[str, str]:
    """NAME -> value of every `export NAME=value` line in a shell script."""
    exports = {}
    for line in script.splitlines():
        words = shlex.split(line, comments=True)
        if len(words) == 2 and words[0] == "export" and "=" in words[1]:
            name, value = words[1].split("=", 1)
            exports[name] = value
    return exports


def assert_lavapipe(exports: dict[str, str], arch: str) -> None:
    icd = exports["VK_DRIVER_FILES"]
    assert "-mesa/" in icd and icd.endswith(f"/share/vulkan/icd.d/lvp_icd.{arch}.json"), icd
    assert exports["VK_ICD_FILENAMES"] == icd
    assert exports["VK_LOADER_LAYERS_DISABLE"] == "~implicit~"


def test_flake_and_stub_parse(nix, repo_root):
    for path in [repo_root / "flake.nix", *sorted((repo_root / STUB).glob("*.nix"))]:
        nix.instantiate("--parse", str(path))


def test_nixpkgs_is_pinned_by_revision(nix, repo_root):
    inputs = json.loads(
        nix.instantiate("--eval", "--strict", "--json", "-E", f"(import {repo_root / 'flake.nix'}).inputs")
    )
    assert inputs == {"nixpkgs": {"url": f"github:NixOS/nixpkgs/{NIXPKGS_REV}"}}


def test_flake_lock_carries_the_pin_and_matches_flake_nix(nix, flake):
    """The committed lock holds exactly the pinned revision and its narHash, and Nix takes it as it is:
    a lock that did not match flake.nix's input would be re-locked, which means downloading nixpkgs.
    (Whether the narHash is nixpkgs' real one can only be seen by downloading it.)"""
    lock_text = (flake / "flake.lock").read_text()
    nodes = json.loads(lock_text)["nodes"]
    assert nodes["root"]["inputs"] == {"nixpkgs": "nixpkgs"}
    locked = nodes["nixpkgs"]["locked"]
    assert (locked["type"], locked["owner"], locked["repo"]) == ("github", "NixOS", "nixpkgs")
    assert (locked["rev"], locked["narHash"]) == (NIXPKGS_REV, NIXPKGS_NAR_HASH)
    nix.nix("flake", "lock", "--offline", "--no-update-lock-file", f"git+file://{flake}")
    assert (flake / "flake.lock").read_text() == lock_text


def all_systems(nix: Nix, command: str) -> list[str]:
    """`nix flake show` and `nix flake check` of newer Nix (2.26 on Debian 13)
    evaluate only the host system's outputs unless given --all-systems (show
    lists the others without their type); Nix 2.8 (Debian 12) evaluates every
    system and has no such option."""
    return ["--all-systems"] if "--all-systems" in nix.nix("flake", command, "--help") else []


def test_flake_show_lists_the_outputs_for_both_systems(nix, flake):
    shown = json.loads(
        nix.nix("flake", "show", "--json", *all_systems(nix, "show"), *flake_args(flake), f"git+file://{flake}")
    )
    for system in SYSTEMS:
        assert {name: app["type"] for name, app in shown["apps"][system].items()} == {name: "app" for name in APPS}
        assert shown["packages"][system]["default"]["type"] == "derivation"
        assert shown["devShells"][system]["default"]["type"] == "derivation"
        assert set(shown["checks"][system]) == CHECKS
        assert all(check["type"] == "derivation" for check in shown["checks"][system].values())


def test_flake_check_evaluates_without_building(nix, flake):
    nix.nix("flake", "check", "--no-build", *all_systems(nix, "check"), *flake_args(flake), f"git+file://{flake}")


def test_apps_run_the_package_on_lavapipe_and_record_nix(nix, flake):
    programs = evaluate(nix, flake, "apps", "builtins.mapAttrs (s: builtins.mapAttrs (n: a: a.program))")
    wrappers = evaluate(
        nix,
        flake,
        "checks",
        "builtins.mapAttrs (s: c: builtins.mapAttrs (n: w: { out = w.outPath; inherit (w) text runtimeEnv; })"
        " { inherit (c) app-default app-bench app-report; })",
    )
    packages = evaluate(nix, flake, "packages", "builtins.mapAttrs (s: p: p.default.outPath)")
    for system, arch in SYSTEMS.items():
        for app, exe in APPS.items():
            wrapper = wrappers[system][f"app-{app}"]
            assert programs[system][app] == f"{wrapper['out']}/bin/{exe}"
            guard = 'if [ "${RT_USE_HOST_VULKAN:-0}" != 1 ]; then'
            assert guard in wrapper["text"], "lavapipe must be forced unless RT_USE_HOST_VULKAN=1"
            assert_lavapipe(shell_exports(wrapper["text"]), arch)
            env = wrapper["runtimeEnv"]
            assert env["RT_NIX"] == "1" and env["RT_NIXPKGS_REV"]  # "unknown" with the stub: it has no revision
            assert env["RT_BINARY"] == f"{packages[system]}/bin/raytracer"
            assert env["RT_BINARY_PAPER_O0"].endswith("-raytracer-paper-o0-0.1.0/bin/raytracer")
            assert env["RT_PYTHON"].endswith("-python3-3.13-env/bin/python3")
        assert f'{packages[system]}/share/raytracer/scripts/bench "$@"' in wrappers[system]["app-bench"]["text"]
        assert f'{packages[system]}/share/raytracer/scripts/report.py "$@"' in wrappers[system]["app-report"]["text"]
        assert f'{packages[system]}/bin/raytracer "$@"' in wrappers[system]["app-default"]["text"]


def test_package_builds_the_profile_preset_with_nixpkgs_tracy_and_tests_on_lavapipe(nix, flake):
    packages = evaluate(
        nix,
        flake,
        "packages",
        "builtins.mapAttrs (s: p: { inherit (p.default) doCheck configurePhase checkPhase postFixup"
        " buildInputs nativeCheckInputs"
        " VK_DRIVER_FILES VK_ICD_FILENAMES VK_LOADER_LAYERS_DISABLE VK_ADD_LAYER_PATH;"
        " commit = p.default.RT_GIT_COMMIT or null; })",
    )
    for system, arch in SYSTEMS.items():
        package = packages[system]
        assert package["doCheck"] is True
        assert "cmake --preset profile " in package["configurePhase"]
        assert "-DRT_TRACY_CLIENT_DIR=/nix/store/" in package["configurePhase"]
        assert package["configurePhase"].split("-DRT_TRACY_CLIENT_DIR=")[1].split()[0].endswith("-source/public")
        assert "ctest" in package["checkPhase"] and "pytest" in package["checkPhase"]
        assert "-DRT_WINDOW=ON" in package["configurePhase"], "the package has the live window"
        assert any(str(p).endswith("-glfw") for p in package["buildInputs"])
        assert any(str(p).endswith("-xorgserver") for p in package["nativeCheckInputs"]), "Xvfb for tests/window"
        assert_lavapipe(package, arch)
        assert package["VK_ADD_LAYER_PATH"].endswith("-vulkan-validation-layers/share/vulkan/explicit_layer.d")
        # The overridden input makes the lock differ from flake.lock, so Nix treats the tree as dirty:
        # Nix 2.8 then gives no revision at all, later versions self.dirtyRev.
        assert package["commit"] is None or len(package["commit"]) == 40
        assert "--set RT_NIX 1" in package["postFixup"]


def test_dev_shell_has_the_tools_and_lavapipe(nix, flake):
    shells = evaluate(
        nix,
        flake,
        "devShells",
        "builtins.mapAttrs (s: d: { inherit (d.default) shellHook RT_TRACY_CLIENT_DIR RT_PYTHON RT_NIX;"
        " packages = map (p: p.name) d.default.packages; })",
    )
    for system, arch in SYSTEMS.items():
        shell = shells[system]
        assert_lavapipe(shell_exports(shell["shellHook"]), arch)
        assert shell["RT_TRACY_CLIENT_DIR"].endswith("-source/public")
        assert shell["RT_NIX"] == "1"
        assert {"tracy-0.11.1", "vulkan-tools", "vulkan-validation-layers", "clang-tools-19", "ruff"} <= set(
            shell["packages"]
        )


def test_the_package_and_its_python_have_every_dependency_of_the_list(nix, flake, repo_root):
    """dependencies.toml reaches the Nix build: each library, test library and
    program the tests run is an input of the package, and each Python package
    of the list (scipy among them) is in the Python that runs the report and pytest."""
    import tomllib

    deps = tomllib.loads((repo_root / "dependencies.toml").read_text()).values()
    package = evaluate(
        nix,
        flake,
        "packages.x86_64-linux.default",
        "p: { inputs = map (d: d.name) (p.buildInputs ++ p.nativeBuildInputs ++ p.nativeCheckInputs);"
        " python = map (d: d.name) (builtins.head (builtins.filter (d: d ? packages) p.buildInputs)).packages; }",
    )
    for dep in deps:
        for attr in dep["nix"].split():
            name = attr.rpartition(".")[2]
            if dep["role"] in {"build", "library", "test-library", "check"}:
                assert any(n == name or n.startswith(f"{name}-") for n in package["inputs"]), attr
            elif dep["role"] == "python":
                assert f"python3.13-{name}" in package["python"], attr
    assert "python3.13-scipy" in package["python"]
