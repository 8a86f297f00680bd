"""build.nix in the run metadata: null, or the nixpkgs revision when the Nix
flake's package or apps run the binary (they set RT_NIX=1 and RT_NIXPKGS_REV)."""

import json
import os
import subprocess

import pytest

SMALL = ["--width", "8", "--height", "6", "--warmup", "0", "--frames", "1", "--quiet"]


def build_nix(raytracer, repo_root, tmp_path, **nix_env):
    env = {k: v for k, v in os.environ.items() if k not in ("RT_NIX", "RT_NIXPKGS_REV")}
    env.update(nix_env)
    csv = tmp_path / "run.csv"
    done = subprocess.run(
        [raytracer, repo_root / "scenes/default.json", *SMALL, "--csv", csv], capture_output=True, text=True, env=env
    )
    assert done.returncode == 0, done.stderr
    return json.loads((tmp_path / "run.meta.json").read_text())["build"]["nix"]


def test_build_nix_is_null_outside_nix(raytracer, repo_root, tmp_path):
    assert build_nix(raytracer, repo_root, tmp_path) is None


@pytest.mark.parametrize("rev, recorded", [("8fd9daa3db09ced9700431c5b7ad0e8ba199b575",) * 2, ("", "unknown")])
def test_build_nix_records_the_nixpkgs_revision(raytracer, repo_root, tmp_path, rev, recorded):
    assert build_nix(raytracer, repo_root, tmp_path, RT_NIX="1", RT_NIXPKGS_REV=rev) == {"nixpkgs_rev": recorded}
