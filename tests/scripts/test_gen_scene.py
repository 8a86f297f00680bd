import itertools
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


# --- the corpus (rtbench/scenes.py's docstring) --------------------------------------


def _inside(inner, outer, slack=1e-3):
    gap = sum((a - b) ** 2 for a, b in zip(inner["position"], outer["position"])) ** 0.5
    return gap + inner["radius"] <= outer["radius"] + slack


@pytest.mark.parametrize("family", scenes.CORPUS_FAMILIES)
def test_each_family_is_named_sized_and_seeded_like_random(family):
    name = f"{family}60"
    assert scenes.family_of(name) == family
    scene = scenes.recipe(name)()
    assert len(scene["spheres"]) == 60
    assert scenes.to_json(scene) == scenes.to_json(scenes.FAMILIES[family](60, seed=60))
    assert scenes.to_json(scenes.FAMILIES[family](60, seed=1)) != scenes.to_json(scene)
    for bad in (f"{family}0", f"{family}07", family):
        assert scenes.recipe(bad) is None


@pytest.mark.parametrize("name", scenes.CORPUS)
def test_corpus_scenes_keep_the_scene_limits_and_the_camera_outside(name):
    max_magnitude, min_length = scenes.schema.scene_limits()
    scene = scenes.recipe(name)()
    cam = scene["camera"]["position"]
    spheres = scene["spheres"]
    for s in spheres:
        assert min_length <= s["radius"] <= max_magnitude
        assert all(abs(v) <= max_magnitude for v in s["position"])
        assert all(0.0 <= c <= 1.0 for c in s["color"])
    # The camera orbits the origin at its height: outside every sphere all
    # the way round (nested's sky holds it, by design).
    orbit = (cam[0] ** 2 + cam[2] ** 2) ** 0.5
    skies = [s for s in spheres if _inside({"position": cam, "radius": 0.0}, s)]
    assert skies == ([spheres[0]] if name.startswith("nested") else [])
    for s in spheres:
        if s in skies:
            continue
        x, y, z = s["position"]
        nearest = (((x * x + z * z) ** 0.5 - orbit) ** 2 + (y - cam[1]) ** 2) ** 0.5
        assert nearest > s["radius"], f"{name}: the orbit passes through {s}"
    size = len(scenes.to_json(scene))
    assert size < 100_000, f"{name}: {size} bytes"


def test_ground_is_one_sphere_of_radius_1000_touching_y0_under_small_ones():
    spheres = scenes.recipe("ground500")()["spheres"]
    radii = sorted(s["radius"] for s in spheres)
    assert radii[-1] == 1000.0 and radii[-2] < 2.0
    assert spheres[0]["radius"] == 1000.0 and spheres[0]["position"][1] + 1000.0 == 0.0
    assert radii[-4:-1] == [1.0, 1.0, 1.0]
    assert all(0.18 <= r <= 0.22 for r in radii[:-4])
    for s in spheres[1:]:  # each rests on the ground, no two overlap
        assert abs(_distance(s, spheres[0]) - 1000.0 - s["radius"]) < 1e-3
    for a in range(1, len(spheres)):
        for b in range(a + 1, len(spheres)):
            assert _distance(spheres[a], spheres[b]) >= spheres[a]["radius"] + spheres[b]["radius"]


def _distance(a, b):
    return sum((p - q) ** 2 for p, q in zip(a["position"], b["position"])) ** 0.5


def test_clusters_hold_most_spheres_and_differ_in_density():
    import random

    scene = scenes.recipe("clusters500")()
    centres, radii, half = scenes.cluster_layout(500, random.Random(500))
    assert len(centres) == scenes.CLUSTERS
    spheres = scene["spheres"]
    held = [
        any(_distance(s, {"position": c}) + s["radius"] <= r + 1e-3 for c, r in zip(centres, radii)) for s in spheres
    ]
    assert sum(held) >= 0.95 * len(spheres)
    assert all(abs(v) <= half + 0.3 for s in spheres for v in s["position"])
    assert max(radii) / min(radii) > 2.0  # densities apart by more than 8x
    assert max(r for r in radii) * 2 < half  # each ball small in its box


def test_crowd_packs_small_spheres_on_a_huge_one_inside_a_ring_of_large_ones():
    spheres = scenes.recipe("crowd500")()["spheres"]
    huge, ring, crowd = spheres[0], spheres[1 : 1 + scenes.RING], spheres[1 + scenes.RING :]
    assert huge["radius"] >= 100.0
    assert all(s["radius"] == 6.0 for s in ring)
    assert all(s["radius"] <= 0.15 for s in crowd)
    reach = max((s["position"][0] ** 2 + s["position"][2] ** 2) ** 0.5 for s in crowd)
    assert min((s["position"][0] ** 2 + s["position"][2] ** 2) ** 0.5 for s in ring) - 6.0 > 5 * reach
    assert all(not _inside(s, huge) and _distance(s, huge) < huge["radius"] + 2.0 for s in crowd)


def test_heavytail_radii_span_a_heavy_tail_within_their_box():
    import statistics

    radii = [s["radius"] for s in scenes.recipe("heavytail500")()["spheres"]]
    assert max(radii) / statistics.median(radii) > 20
    assert min(radii) >= scenes.PARETO_MIN - 1e-4
    assert sum(r > 10 * statistics.median(radii) for r in radii) >= 3  # a tail, not one outlier


def test_nested_spheres_sit_inside_their_parents():
    spheres = scenes.recipe("nested200")()["spheres"]
    sky = spheres[0]
    assert all(_inside(s, sky) for s in spheres[1:])
    # A nest is written outside in: each sphere lies in the one before it, or starts a nest.
    children = [s for parent, s in itertools.pairwise(spheres[1:]) if _inside(s, parent)]
    assert len(children) >= len(spheres) // 2
    for parent, s in itertools.pairwise(spheres[1:]):
        if s["radius"] < parent["radius"] and _distance(s, parent) < parent["radius"]:
            assert _inside(s, parent, slack=0.0)
    concentric = [
        s for parent, s in itertools.pairwise(spheres[1:]) if _inside(s, parent) and _distance(s, parent) == 0
    ]
    assert 0 < len(concentric) < len(children)


def test_the_families_draw_only_random():
    """Random.random() is the one method whose bytes every Python 3 shares;
    gauss, choice, randrange and paretovariate have changed between releases."""
    import inspect

    source = inspect.getsource(scenes)
    body = source[source.index("# --- the corpus") :]
    for method in ("gauss", "choice", "randrange", "randint", "paretovariate", "uniform(", "shuffle", "sample("):
        assert f"rng.{method}" not in body, method
