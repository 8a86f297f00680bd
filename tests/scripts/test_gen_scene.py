import json
import subprocess
import sys

import pytest

from rtbench import scenes


def test_regenerated_scenes_are_byte_identical(repo_root, tmp_path):
    committed_scenes = sorted(p.stem for p in (repo_root / "scenes").glob("*.json"))
    assert sorted(scenes.COMMITTED) == committed_scenes
    subprocess.run(
        [sys.executable, repo_root / "scripts/gen_scene.py", *scenes.COMMITTED, "-o", tmp_path],
        check=True,
        capture_output=True,
    )
    for name in scenes.COMMITTED:
        committed = (repo_root / "scenes" / f"{name}.json").read_bytes()
        assert (tmp_path / f"{name}.json").read_bytes() == committed, f"scenes/{name}.json drifted from its generator"


def test_scene_sizes_match_their_names():
    assert len(scenes.recipe("default")()["spheres"]) == 3
    assert len(scenes.recipe("random20")()["spheres"]) == 20
    assert len(scenes.recipe("random7")()["spheres"]) == 7
    assert scenes.recipe("random7")() == scenes.random_scene(7, seed=7)
    for name in ("random0", "random", "random07", "default2"):
        assert scenes.recipe(name) is None


def _extent(scene):
    """(largest |y|, largest distance from the axis + radius, camera orbit radius)."""
    spheres = scene["spheres"]
    cam = scene["camera"]["position"]
    return (
        max(abs(s["position"][1]) for s in spheres),
        max((s["position"][0] ** 2 + s["position"][2] ** 2) ** 0.5 + s["radius"] for s in spheres),
        (cam[0] ** 2 + cam[2] ** 2) ** 0.5,
    )


@pytest.mark.parametrize("count", [300, 2000])
def test_large_scenes_scale_the_cluster_of_the_disc_limit_in_3d(count):
    """Above DISC_LIMIT the cluster and the camera's orbit grow by cbrt(N / limit)
    in every direction: the density of random100, seen from proportionally farther."""
    limit = scenes.DISC_LIMIT
    scale = (count / limit) ** (1 / 3)
    height, reach, orbit = _extent(scenes.random_scene(count, seed=3))
    base_height, base_reach, base_orbit = _extent(scenes.random_scene(limit, seed=3))
    assert orbit == pytest.approx(base_orbit * scale, rel=1e-4)
    assert base_height <= 1.5 < height <= 1.5 * scale
    assert base_reach * scale * 0.9 < reach <= (base_orbit - 4.0) * scale  # spread fills its disc, never the orbit
    cam = scenes.random_scene(count, seed=3)["camera"]["position"]
    assert cam[1] / orbit == pytest.approx(0.35, rel=1e-4)  # the same view angle at every N


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
        [sys.executable, repo_root / "scripts/gen_scene.py", "--random", "7", "--seed", "3", "-o", tmp_path],
        check=True,
        capture_output=True,
    )
    scene = tmp_path / "random7-seed3.json"
    assert len(json.loads(scene.read_text())["spheres"]) == 7
    done = subprocess.run(
        [raytracer, "--quiet", "--width", "16", "--height", "8", "--frames", "1", "--warmup", "0", scene]
    )
    assert done.returncode == 0


@pytest.mark.parametrize(
    "args", [["nosuchscene", "-o", "."], ["--random", "0", "-o", "."], ["default", "-o", "/nonexistent"]]
)
def test_bad_arguments_are_rejected(repo_root, args):
    done = subprocess.run([sys.executable, repo_root / "scripts/gen_scene.py", *args], capture_output=True, text=True)
    assert done.returncode == 2
    assert "error" in done.stderr


def test_a_scene_beyond_the_limits_is_refused_before_it_is_generated(repo_root):
    from rtbench import scenes, schema

    max_magnitude, _ = schema.scene_limits()
    # The cluster grows as cbrt(N): 4.5e16 spheres would reach 1e6. Refused
    # before a single sphere is drawn, so this costs nothing.
    with pytest.raises(ValueError, match="beyond the scene limit"):
        scenes.random_scene(10**17, seed=1)
    spread, _, orbit = scenes._layout(10**7)  # ten million spheres stay far inside
    assert max(spread, orbit) < max_magnitude / 100
    done = subprocess.run(
        [sys.executable, str(repo_root / "scripts/gen_scene.py"), "random100000000000000000", "-o", "/tmp"],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 2 and "beyond the scene limit" in done.stderr


def test_the_render_model_states_the_schema_limits(repo_root):
    from rtbench import schema

    def written(value: float) -> str:  # 1e6, 1e-6 as the document writes them
        return f"{value:.0e}".replace("e+0", "e").replace("e-0", "e-")

    max_magnitude, min_length = schema.scene_limits()
    text = (repo_root / "docs/render-model.md").read_text()
    limits = text[text.index("**Limits**") : text.index("**Rejection.**")]
    assert f"[-{written(max_magnitude)}, {written(max_magnitude)}]" in limits
    assert f"at least {written(min_length)}" in limits
