"""The profile keys of the GPU renderer's walks (gpu_bvhs): which
configurations they multiply, the command lines and names they give them,
the overrides that match them, the errors for values that cannot be used,
the refusal of the retired keys (gpu_schedules, gpu_paths), and what the
gpu-machine and scene-size profiles run."""

import re
from collections import Counter
from pathlib import Path

import profile_test_support as support
import pytest
from profile_test_support import EVERY_RENDERER, argv, flag_value

from rtbench import configurations, names, profiles
from rtbench.profiles import ProfileError

PATH = Path("gpu-axes-test.toml")
# Hand-written: the schema's walks and the flags the raytracer takes for the GPU axes.
BVHS = ["binary", "wide", "grid"]
FLAGS = {"gpu_bvh": "--gpu-bvh", "gpu_rt_reorder": "--gpu-rt-reorder"}
RETIRED_KEYS = {"gpu_schedules": ["pixel", "persistent"], "gpu_paths": ["megakernel", "wavefront"]}
RETIRED_FLAGS = ["--gpu-schedule", "--gpu-path"]


def profile(**keys):
    return support.profile(PATH, **keys)


def expand(**keys):
    return support.expand(PATH, **keys)


def test_the_schema_lists_the_walks_this_test_knows():
    assert names.GPU_BVHS == BVHS
    assert configurations.GPU_FLAGS == FLAGS


def test_the_walks_multiply_only_the_gpu_renderer_with_accel_bvh():
    configs = expand(accels=["none", "bvh"], renderers=EVERY_RENDERER, gpu_bvhs=BVHS)
    by_cell = {}
    for c in configs:
        by_cell.setdefault((c.renderer, c.accel), []).append(c.gpu_bvh)
    for (renderer, accel), walks in by_cell.items():
        if renderer == "gpu" and accel == "bvh":
            assert sorted(walks) == sorted(BVHS)
        else:
            assert walks == [""], (renderer, accel)
        # gpu_rt has its own axis, at its default here; no other renderer has it.
        assert {c.gpu_rt_reorder for c in configs if c.renderer == renderer} == {"none" if renderer == "gpu_rt" else ""}
    for c in configs:
        for column, flag in FLAGS.items():
            assert flag_value(c, flag) == (c.gpu_axes[column] or None), (c.id, flag)
        assert not set(RETIRED_FLAGS) & set(argv(c)), "the retired flags are refused by the raytracer"
        assert c.describe()["gpu_bvh"] == c.gpu_bvh
    # gpu: 3 with the BVH (or the grid) + 1 brute force; the others once per accel (embree and gpu_rt once).
    assert len(configs) == 3 + 1 + 2 * (len(names.RENDERERS) - 1) - 2


def test_the_defaults_run_the_gpu_as_before_and_leave_its_names_as_they_were():
    configs = expand(accels=["none", "bvh"], renderers={"gpu": {}})
    assert [(c.id, c.gpu_bvh) for c in configs] == [
        ("random100-gpu-optimized", ""),
        ("random100-gpu-optimized-bvh", "binary"),
    ]
    # Named on the command line all the same (as --traversal packet is), so a run says what it asked for.
    assert flag_value(configs[1], "--gpu-bvh") == "binary" and flag_value(configs[0], "--gpu-bvh") is None


def test_a_walk_names_its_configuration_where_it_is_not_the_default():
    ids = {c.gpu_bvh: c.id for c in expand(accels=["bvh"], renderers={"gpu": {"size": ["64x48"]}}, gpu_bvhs=BVHS)}
    assert ids == {
        "binary": "random100-gpu-optimized-bvh-size64x48",
        "wide": "random100-gpu-optimized-bvh-wide-size64x48",
        "grid": "random100-gpu-optimized-bvh-grid-size64x48",
    }


def test_counters_reach_the_gpu_renderer_too():
    (config,) = expand(accels=["bvh"], counters=True, renderers={"gpu": {}})
    assert config.counters and configurations.COUNTERS_FLAG in argv(config)


def test_overrides_match_the_walks_and_never_a_configuration_without_that_axis():
    configs = expand(
        accels=["none", "bvh"],
        renderers={"gpu": {}, "simd_tbb": {}},
        gpu_bvhs=BVHS,
        overrides=[
            {"gpu_bvhs": ["grid"], "skip": True},
            {"gpu_bvhs": ["wide"], "frames": 9},
        ],
    )
    ids = {c.id: c for c in configs}
    assert "random100-gpu-optimized-bvh-grid" not in ids
    assert ids["random100-gpu-optimized-bvh-wide"].frames == 9
    assert ids["random100-gpu-optimized-bvh"].frames == profiles.TOP_RULES["frames"].default
    # Brute force has no BVH: gpu_bvhs never matches it; simd_tbb has none of the axes.
    assert ids["random100-gpu-optimized"].frames == profiles.TOP_RULES["frames"].default
    for simd in ("random100-simd_tbb-optimized", "random100-simd_tbb-optimized-bvh"):
        assert ids[simd].frames == profiles.TOP_RULES["frames"].default


@pytest.mark.parametrize(
    "keys, message",
    [
        ({"gpu_bvhs": ["binary", "quad"]}, "gpu_bvhs must be a list, each one of binary, wide, grid"),
        ({"gpu_bvhs": ["wide", "wide"]}, "gpu_bvhs names a value twice"),
        ({"accels": ["none"], "gpu_bvhs": ["wide"]}, "gpu_bvhs: applies to the gpu renderer with accel bvh only"),
        ({"overrides": [{"gpu_bvhs": ["quad"], "skip": True}]}, "overrides[0].gpu_bvhs must be a list"),
    ],
)
def test_bad_gpu_keys_name_the_file_and_key(keys, message):
    with pytest.raises(ProfileError, match=re.escape(message)) as e:
        profile(accels=keys.pop("accels", ["bvh"]), renderers={"gpu": {}}, **keys)
    assert str(e.value).startswith(f"{PATH}: ")


def test_a_walk_besides_the_default_needs_the_gpu_renderer():
    with pytest.raises(ProfileError, match=re.escape("gpu_bvhs: applies to the gpu renderer only")):
        profile(accels=["bvh"], renderers={"simd_tbb": {}}, gpu_bvhs=BVHS)
    # The default alone is what every profile says without the key: no error.
    profile(accels=["bvh"], renderers={"simd_tbb": {}}, gpu_bvhs=BVHS[:1])


# The retired axes' keys (schema: retired_gpu_variants) are refused with any
# value, at the top and in an override, naming what the GPU renderer runs now
# and where the retired variants' measurements are.
@pytest.mark.parametrize("key, values", RETIRED_KEYS.items())
@pytest.mark.parametrize("in_override", [False, True])
def test_the_retired_keys_are_refused_naming_their_record(key, values, in_override):
    for value in values:
        keys = {"overrides": [{key: [value], "skip": True}]} if in_override else {key: [value]}
        with pytest.raises(ProfileError) as e:
            profile(accels=["bvh"], renderers={"gpu": {}}, **keys)
        where = "overrides[0]." if in_override else ""
        assert str(e.value).startswith(f"{PATH}: {where}{key}: retired: the GPU renderer always runs {values[0]} now")
        assert f"the retired {values[1]} are in docs/experiments/gpu-traversal.md" in str(e.value)


def expand_profile(name, cores=16):
    p = profiles.load_profile(name)
    return configurations.expand(p, [profiles.resolve_scene(s) for s in p.scenes], cores)


def test_the_gpu_machine_profile_runs_every_gpu_walk_on_random100():
    configs = expand_profile("gpu-machine")
    gpu_bvh = [c for c in configs if c.renderer == "gpu" and c.accel == "bvh"]
    cells = Counter((c.scene, c.variant.label, (c.width, c.height)) for c in gpu_bvh)
    assert cells == {("random100", stage, size): 3 for stage in names.STAGES for size in ((800, 600), (1920, 1080))}
    for cell in cells:
        walks = {c.gpu_bvh for c in gpu_bvh if (c.scene, c.variant.label, (c.width, c.height)) == cell}
        assert walks == set(BVHS)
    # Brute force as before: every scene and stage, both sizes.
    brute = [c for c in configs if c.renderer == "gpu" and c.accel == "none"]
    assert len(brute) == 18 and {c.gpu_bvh for c in brute} == {""}
    assert all(c.frames == 40 for c in configs if c.renderer == "gpu")
    # No CPU renderer gains the BVH; embree and gpu_rt keep their own.
    assert {c.renderer for c in configs if c.accel == "bvh"} == {"gpu", "gpu_rt", "embree"}
    assert sum(c.renderer == "embree" for c in configs) == 9
    assert len(configs) == 77 + 18 + 24


def test_the_scene_size_profile_runs_every_gpu_walk_at_every_count():
    configs = expand_profile("scene-size")
    gpu = [c for c in configs if c.renderer == "gpu"]
    for scene in {c.scene for c in configs}:
        here = [c for c in gpu if c.scene == scene]
        assert sorted(c.gpu_bvh for c in here if c.accel == "bvh") == sorted(BVHS), scene
        assert {c.gpu_bvh for c in here if c.accel == "none"} <= {""}
    assert {(c.warmup, c.frames) for c in gpu} == {(3, 20)}
    # gpu_rt beside it at every count, without reordering, measured as the gpu.
    rt = [c for c in configs if c.renderer == "gpu_rt"]
    assert sorted(c.scene for c in rt) == sorted({c.scene for c in configs})
    assert {(c.accel, c.gpu_rt_reorder, c.warmup, c.frames) for c in rt} == {("bvh", "none", 3, 20)}
    # The other renderers as they were (frames, cells).
    assert all(not any(c.gpu_axes.values()) for c in configs if c.renderer not in ("gpu", "gpu_rt"))
