import json
import subprocess
import sys

import pytest
from rtbench import scenes


def test_regenerated_scenes_are_byte_identical(repo_root, tmp_path):
    subprocess.run(
        [sys.executable, repo_root / "scripts/gen_scene.py", "default", "random20", "random100", "-o", tmp_path],
        check=True,
        capture_output=True,
    )
    for name in ("default", "random20", "random100"):
        committed = (repo_root / "scenes" / f"{name}.json").read_bytes()
        assert (tmp_path / f"{name}.json").read_bytes() == committed, f"scenes/{name}.json drifted from its generator"


def test_scene_sizes_match_their_names():
    assert len(scenes.RECIPES["default"]()["spheres"]) == 3
    assert len(scenes.RECIPES["random20"]()["spheres"]) == 20
    assert len(scenes.RECIPES["random100"]()["spheres"]) == 100


def test_seed_decides_the_scene():
    a = scenes.to_json(scenes.random_scene(10, seed=1))
    b = scenes.to_json(scenes.random_scene(10, seed=1))
    c = scenes.to_json(scenes.random_scene(10, seed=2))
    assert a == b
    assert a != c


def test_spheres_stay_inside_the_camera_orbit():
    scene = scenes.random_scene(300, seed=5)
    cam = scene["camera"]["position"]
    orbit_radius = (cam[0] ** 2 + cam[2] ** 2) ** 0.5
    for s in scene["spheres"]:
        x, _, z = s["position"]
        assert (x * x + z * z) ** 0.5 + s["radius"] < orbit_radius
        assert all(0.0 <= c <= 1.0 for c in s["color"])


def test_generated_scene_renders(raytracer, repo_root, tmp_path):
    subprocess.run(
        [sys.executable, repo_root / "scripts/gen_scene.py", "--random", "7", "--seed", "3", "-o", tmp_path], check=True, capture_output=True
    )
    scene = tmp_path / "random7-seed3.json"
    assert len(json.loads(scene.read_text())["spheres"]) == 7
    done = subprocess.run([raytracer, "--quiet", "--width", "16", "--height", "8", "--frames", "1", "--warmup", "0", scene])
    assert done.returncode == 0


@pytest.mark.parametrize("args", [["nosuchscene", "-o", "."], ["--random", "0", "-o", "."], ["default", "-o", "/nonexistent"]])
def test_bad_arguments_are_rejected(repo_root, args):
    done = subprocess.run([sys.executable, repo_root / "scripts/gen_scene.py", *args], capture_output=True, text=True)
    assert done.returncode == 2
    assert "error" in done.stderr
