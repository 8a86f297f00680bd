"""The profile keys the GPU machine's reference run needs: overrides that
match thread counts and lane widths, the `size` axis, and the gpu-machine
profile they express."""

import re
from collections import Counter
from pathlib import Path

import pytest

from rtbench import configurations, profiles

SCENES = [Path("scenes/default.json"), Path("scenes/random100.json")]


def profile(**renderers_and_overrides):
    raw = {
        "description": "test",
        "scenes": ["default", "random100"],
        "stages": ["original", "optimized"],
        **renderers_and_overrides,
    }
    return profiles.parse_profile(raw, Path("test.toml"))


def test_an_override_matches_thread_counts_and_lane_widths():
    p = profile(
        renderers={"simd_tbb": {"threads": [1, 2, 4], "lanes": [4, "native"]}},
        overrides=[
            {"scenes": ["default"], "threads": [1, 2], "skip": True},
            {"lanes": ["native"], "threads": [4], "frames": 9},
        ],
    )
    configs = {c.id: c for c in configurations.expand(p, SCENES, 4)}
    assert sorted(i for i in configs if i.startswith("default-")) == [
        "default-simd_tbb-optimized-threads4-lanes4",
        "default-simd_tbb-optimized-threads4-lanesnative",
        "default-simd_tbb-original-threads4-lanes4",
        "default-simd_tbb-original-threads4-lanesnative",
    ]
    assert len([i for i in configs if i.startswith("random100-")]) == 12
    assert configs["random100-simd_tbb-original-threads4-lanesnative"].frames == 9
    assert configs["random100-simd_tbb-original-threads4-lanes4"].frames == profiles.TOP_RULES["frames"].default


def test_an_override_naming_an_axis_never_matches_a_renderer_without_it():
    p = profile(
        renderers={"sequential": {}, "tbb_only": {"threads": [1, 2]}}, overrides=[{"threads": [1], "skip": True}]
    )
    ids = [c.id for c in configurations.expand(p, SCENES[:1], 2)]
    assert "default-sequential-original" in ids and "default-tbb_only-original-threads1" not in ids


@pytest.mark.parametrize(
    "override, message", [({"threads": ["all"]}, "overrides[0].threads"), ({"lanes": [3]}, "overrides[0].lanes")]
)
def test_override_axis_values_are_checked(override, message):
    with pytest.raises(profiles.ProfileError, match=re.escape(message)):
        profile(renderers={"simd_tbb": {}}, overrides=[override])


def test_the_size_axis_sets_width_and_height_and_names_the_configuration():
    p = profile(renderers={"gpu": {"size": ["800x600", "1920x1080"]}})
    configs = {c.id: c for c in configurations.expand(p, SCENES[:1], 2)}
    big = configs["default-gpu-optimized-size1920x1080"]
    assert (big.width, big.height) == (1920, 1080)
    argv = big.argv(Path("raytracer"), Path("x.csv"), Path("x.meta.json"))
    assert argv[argv.index("--width") + 1] == "1920" and argv[argv.index("--height") + 1] == "1080"
    assert "size" not in " ".join(argv) and argv.count("--width") == 1
    assert (
        configs["default-gpu-optimized-size800x600"].width,
        configs["default-gpu-optimized-size800x600"].height,
    ) == (800, 600)


def test_a_malformed_size_names_the_key():
    with pytest.raises(profiles.ProfileError, match=r"renderers\.gpu\.size must be an image size"):
        profile(renderers={"gpu": {"size": "1920*1080"}})


def test_the_gpu_machine_profile_on_16_cores():
    p = profiles.load_profile("gpu-machine")
    configs = configurations.expand(p, [profiles.resolve_scene(s) for s in p.scenes], 16)
    assert Counter(c.renderer for c in configs) == {
        "sequential": 9,
        "simd_tbb": 18,
        "simd_only": 10,
        "tbb_only": 13,
        # 18 of brute force, 18 of the BVH or grid in its 3 walks (random100, 3 stages, 2 sizes).
        "gpu": 18 + 18,
        # Every scene and stage at both sizes without reordering, and with hit reordering on random100.
        "gpu_rt": 18 + 6,
        "embree": 9,
    }
    scaling = [
        c for c in configs if dict(c.axes).get("threads") not in (None, "16") or dict(c.axes).get("lanes") == "4"
    ]
    assert {(c.scene, c.variant.label) for c in scaling} == {("random100", "optimized")}
    threads = {(c.renderer, dict(c.axes).get("lanes")): set() for c in configs}
    for c in configs:
        if c.scene == "random100" and c.variant.label == "optimized" and "threads" in dict(c.axes):
            threads[(c.renderer, dict(c.axes).get("lanes"))].add(int(dict(c.axes)["threads"]))
    expected = {1, 2, 4, 8, 16}
    assert threads[("simd_tbb", "4")] == threads[("simd_tbb", "native")] == threads[("tbb_only", None)] == expected
    sizes = Counter((c.width, c.height) for c in configs if c.renderer == "gpu")
    assert sizes == {(800, 600): 18, (1920, 1080): 18}
    sizes = Counter((c.width, c.height) for c in configs if c.renderer == "gpu_rt")
    assert sizes == {(800, 600): 12, (1920, 1080): 12}


def test_an_override_of_a_thread_count_does_not_reach_all_cores_of_that_count():
    """On 2 cores "all" is threads 2 on the command line, but an override of
    the scaling point 2 does not skip it: the profile wrote "all"; where both
    give the same command line it runs once."""
    p = profile(
        renderers={"tbb_only": {"threads": [1, 2, "all"]}},
        overrides=[{"scenes": ["default"], "threads": [1, 2], "skip": True}],
    )
    ids = [c.id for c in configurations.expand(p, SCENES, 2)]
    assert sorted(i for i in ids if i.startswith("default-")) == [
        "default-tbb_only-optimized-threads2",
        "default-tbb_only-original-threads2",
    ]
    assert sorted(i for i in ids if i.startswith("random100-")) == [
        "random100-tbb_only-optimized-threads1",
        "random100-tbb_only-optimized-threads2",
        "random100-tbb_only-original-threads1",
        "random100-tbb_only-original-threads2",
    ]


def test_the_gpu_machine_profile_on_our_2_cores_keeps_the_paper_matrix_on_all_cores():
    """What scripts/compare.py --all-cores needs to match this machine's run
    with the GPU machine's: every scene and stage has the CPU renderers at
    threads 2 (all cores here); the scaling points only on random100 /
    optimized."""
    p = profiles.load_profile("gpu-machine")
    configs = configurations.expand(p, [profiles.resolve_scene(s) for s in p.scenes], 2)
    for renderer in ("simd_tbb", "tbb_only", "embree"):
        cells = {
            (c.scene, c.variant.label)
            for c in configs
            if c.renderer == renderer and dict(c.axes)["threads"] == "2" and dict(c.axes).get("lanes") != "4"
        }
        assert len(cells) == 9, renderer
    above = {(c.scene, c.variant.label) for c in configs if int(dict(c.axes).get("threads", 0)) > 2}
    assert above == {("random100", "optimized")}
    assert len(configs) == len({c.id for c in configs})
