"""The profile keys of the GPU renderer's variants (gpu_bvhs, gpu_schedules,
gpu_paths): which configurations they multiply, the command lines and names
they give them, the overrides that match them, the errors for values that
cannot be used, and what the gpu-machine and scene-size profiles run."""

import itertools
import re
from collections import Counter
from pathlib import Path

import profile_test_support as support
import pytest
from profile_test_support import EVERY_RENDERER, argv, flag_value

from rtbench import configurations, names, profiles
from rtbench.profiles import ProfileError

PATH = Path("gpu-axes-test.toml")
# Hand-written: the schema's variants and the flags the raytracer takes for them.
BVHS, SCHEDULES, PATHS = ["binary", "wide", "grid"], ["pixel", "persistent"], ["megakernel", "wavefront"]
FLAGS = {
    "gpu_bvh": "--gpu-bvh",
    "gpu_schedule": "--gpu-schedule",
    "gpu_path": "--gpu-path",
    "gpu_rt_reorder": "--gpu-rt-reorder",
}
EVERY_VARIANT = {"gpu_bvhs": BVHS, "gpu_schedules": SCHEDULES, "gpu_paths": PATHS}


def profile(**keys):
    return support.profile(PATH, **keys)


def expand(**keys):
    return support.expand(PATH, **keys)


def variant(config):
    return (config.gpu_bvh, config.gpu_schedule, config.gpu_path)


def test_the_schema_lists_the_variants_this_test_knows():
    assert (names.GPU_BVHS, names.GPU_SCHEDULES, names.GPU_PATHS) == (BVHS, SCHEDULES, PATHS)
    assert configurations.GPU_FLAGS == FLAGS


def test_the_variants_multiply_only_the_gpu_renderer_and_its_bvh_only_with_accel_bvh():
    configs = expand(accels=["none", "bvh"], renderers=EVERY_RENDERER, **EVERY_VARIANT)
    by_cell = {}
    for c in configs:
        by_cell.setdefault((c.renderer, c.accel), []).append(variant(c))
    for (renderer, accel), variants in by_cell.items():
        if renderer == "gpu" and accel == "bvh":
            assert sorted(variants) == sorted(itertools.product(BVHS, SCHEDULES, PATHS))
        elif renderer == "gpu":
            assert sorted(variants) == sorted(itertools.product([""], SCHEDULES, PATHS))
        else:
            assert variants == [("", "", "")], (renderer, accel)
        # gpu_rt has its own axis, at its default here; no other renderer has it.
        assert {c.gpu_rt_reorder for c in configs if c.renderer == renderer} == {"none" if renderer == "gpu_rt" else ""}
    for c in configs:
        for column, flag in FLAGS.items():
            assert flag_value(c, flag) == (c.gpu_axes[column] or None), (c.id, flag)
        assert c.describe()["gpu_schedule"] == c.gpu_schedule
    # gpu: 12 with the BVH (or the grid) + 4 brute force; the others once per accel (embree and gpu_rt once).
    assert len(configs) == 12 + 4 + 2 * (len(names.RENDERERS) - 1) - 2


def test_the_defaults_run_the_gpu_as_before_and_leave_its_names_as_they_were():
    configs = expand(accels=["none", "bvh"], renderers={"gpu": {}})
    assert [(c.id, variant(c)) for c in configs] == [
        ("random100-gpu-optimized", ("", "pixel", "megakernel")),
        ("random100-gpu-optimized-bvh", ("binary", "pixel", "megakernel")),
    ]
    # Named on the command line all the same (as --traversal packet is), so a run says what it asked for.
    assert flag_value(configs[1], "--gpu-bvh") == "binary" and flag_value(configs[0], "--gpu-bvh") is None
    assert flag_value(configs[0], "--gpu-path") == "megakernel"


def test_a_variant_names_its_configuration_where_it_is_not_the_default():
    ids = {variant(c): c.id for c in expand(accels=["bvh"], renderers={"gpu": {"size": ["64x48"]}}, **EVERY_VARIANT)}
    assert ids[("wide", "pixel", "megakernel")] == "random100-gpu-optimized-bvh-wide-size64x48"
    assert ids[("binary", "persistent", "wavefront")] == "random100-gpu-optimized-bvh-persistent-wavefront-size64x48"
    assert ids[("wide", "persistent", "wavefront")] == "random100-gpu-optimized-bvh-wide-persistent-wavefront-size64x48"
    assert ids[("grid", "pixel", "megakernel")] == "random100-gpu-optimized-bvh-grid-size64x48"
    assert len(set(ids.values())) == 12


def test_counters_reach_the_gpu_renderer_too():
    (config,) = expand(accels=["bvh"], counters=True, renderers={"gpu": {}})
    assert config.counters and configurations.COUNTERS_FLAG in argv(config)


def test_overrides_match_the_variants_and_never_a_configuration_without_that_axis():
    configs = expand(
        accels=["none", "bvh"],
        renderers={"gpu": {}, "simd_tbb": {}},
        gpu_bvhs=BVHS,
        gpu_paths=PATHS,
        overrides=[
            {"accels": ["none"], "gpu_paths": ["wavefront"], "skip": True},
            {"gpu_bvhs": ["wide"], "frames": 9},
            {"gpu_paths": ["megakernel"], "warmup": 4},
        ],
    )
    ids = {c.id: c for c in configs}
    assert "random100-gpu-optimized-wavefront" not in ids and "random100-gpu-optimized-bvh-wavefront" in ids
    assert ids["random100-gpu-optimized-bvh-wide"].frames == 9
    assert ids["random100-gpu-optimized-bvh-wide-wavefront"].frames == 9
    assert ids["random100-gpu-optimized-bvh"].frames == profiles.TOP_RULES["frames"].default
    # Brute force has no BVH: gpu_bvhs never matches it; simd_tbb has none of the axes.
    assert ids["random100-gpu-optimized"].frames == profiles.TOP_RULES["frames"].default
    assert ids["random100-gpu-optimized"].warmup == 4 and ids["random100-gpu-optimized-bvh-wavefront"].warmup == 1
    for simd in ("random100-simd_tbb-optimized", "random100-simd_tbb-optimized-bvh"):
        assert (ids[simd].frames, ids[simd].warmup) == (profiles.TOP_RULES["frames"].default, 1)


@pytest.mark.parametrize(
    "keys, message",
    [
        ({"gpu_bvhs": ["binary", "quad"]}, "gpu_bvhs must be a list, each one of binary, wide, grid"),
        ({"gpu_schedules": "persistent"}, "gpu_schedules must be a list"),
        ({"gpu_paths": ["wavefront", "wavefront"]}, "gpu_paths names a value twice"),
        ({"accels": ["none"], "gpu_bvhs": ["wide"]}, "gpu_bvhs: applies to the gpu renderer with accel bvh only"),
        ({"overrides": [{"gpu_schedules": ["lazy"], "skip": True}]}, "overrides[0].gpu_schedules must be a list"),
    ],
)
def test_bad_gpu_keys_name_the_file_and_key(keys, message):
    with pytest.raises(ProfileError, match=re.escape(message)) as e:
        profile(accels=keys.pop("accels", ["bvh"]), renderers={"gpu": {}}, **keys)
    assert str(e.value).startswith(f"{PATH}: ")


@pytest.mark.parametrize("key", ["gpu_bvhs", "gpu_schedules", "gpu_paths"])
def test_a_variant_besides_the_default_needs_the_gpu_renderer(key):
    with pytest.raises(ProfileError, match=re.escape(f"{key}: applies to the gpu renderer only")):
        profile(accels=["bvh"], renderers={"simd_tbb": {}}, **{key: EVERY_VARIANT[key]})
    # The default alone is what every profile says without the key: no error.
    profile(accels=["bvh"], renderers={"simd_tbb": {}}, **{key: EVERY_VARIANT[key][:1]})


def expand_profile(name, cores=16):
    p = profiles.load_profile(name)
    return configurations.expand(p, [profiles.resolve_scene(s) for s in p.scenes], cores)


def test_the_gpu_machine_profile_runs_the_gpu_bvh_in_every_variant_on_random100():
    configs = expand_profile("gpu-machine")
    gpu_bvh = [c for c in configs if c.renderer == "gpu" and c.accel == "bvh"]
    cells = Counter((c.scene, c.variant.label, (c.width, c.height)) for c in gpu_bvh)
    assert cells == {("random100", stage, size): 12 for stage in names.STAGES for size in ((800, 600), (1920, 1080))}
    for cell in cells:
        variants = {variant(c) for c in gpu_bvh if (c.scene, c.variant.label, (c.width, c.height)) == cell}
        assert variants == set(itertools.product(BVHS, SCHEDULES, PATHS))
    # Brute force as before: every scene and stage, both sizes, the default variant only.
    brute = [c for c in configs if c.renderer == "gpu" and c.accel == "none"]
    assert len(brute) == 18 and {variant(c) for c in brute} == {("", "pixel", "megakernel")}
    assert all(c.frames == 40 for c in configs if c.renderer == "gpu")
    # No CPU renderer gains the BVH; embree and gpu_rt keep their own.
    assert {c.renderer for c in configs if c.accel == "bvh"} == {"gpu", "gpu_rt", "embree"}
    assert sum(c.renderer == "embree" for c in configs) == 9
    assert len(configs) == 77 + 72 + 24


def test_the_scene_size_profile_runs_the_gpu_bvh_in_every_variant_at_every_count():
    configs = expand_profile("scene-size")
    gpu = [c for c in configs if c.renderer == "gpu"]
    for scene in {c.scene for c in configs}:
        here = [c for c in gpu if c.scene == scene]
        assert sorted(variant(c) for c in here if c.accel == "bvh") == sorted(
            itertools.product(BVHS, SCHEDULES, PATHS)
        ), scene
        assert {variant(c) for c in here if c.accel == "none"} <= {("", "pixel", "megakernel")}
    assert {(c.warmup, c.frames) for c in gpu} == {(3, 20)}
    # gpu_rt beside it at every count, without reordering, measured as the gpu.
    rt = [c for c in configs if c.renderer == "gpu_rt"]
    assert sorted(c.scene for c in rt) == sorted({c.scene for c in configs})
    assert {(c.accel, c.gpu_rt_reorder, c.warmup, c.frames) for c in rt} == {("bvh", "none", 3, 20)}
    # The other renderers as they were (frames, cells).
    assert all(not any(c.gpu_axes.values()) for c in configs if c.renderer not in ("gpu", "gpu_rt"))
