"""The profile keys of the traversal axis (traversals, hybrid_thresholds) and
counters: which configurations they multiply or reach, the command lines and
names they give them, and the errors for values that cannot be used."""

import re
from pathlib import Path

import profile_test_support as support
import pytest
from profile_test_support import EVERY_RENDERER, argv, flag_value

from rtbench import configurations, names, profiles
from rtbench.profiles import ProfileError

PATH = Path("traversal-test.toml")


def profile(**keys):
    return support.profile(PATH, **keys)


def expand(**keys):
    return support.expand(PATH, **keys)


def test_traversals_multiply_only_the_simd_kernel_on_the_bvh():
    configs = expand(accels=["none", "bvh"], traversals=list(names.TRAVERSALS), renderers=EVERY_RENDERER)
    walked = {}
    for c in configs:
        walked.setdefault((c.renderer, c.accel), []).append(c.traversal)
    for (renderer, accel), traversals in walked.items():
        # Hand-written expectation: simd_tbb and simd_only are the SIMD kernel's renderers.
        if renderer in ("simd_tbb", "simd_only") and accel == "bvh":
            assert traversals == list(names.TRAVERSALS), renderer
        else:
            assert traversals == [""], (renderer, accel)
    for c in configs:
        assert flag_value(c, configurations.TRAVERSAL_FLAG) == (c.traversal or None)
    # Embree and gpu_rt keep their own BVH and run once; brute force and the scalar kernel once per accel.
    assert len(configs) == 2 * len(names.RENDERERS) - len(names.OWN_ACCEL) + 2 * (len(names.TRAVERSALS) - 1)


def test_a_traversal_names_its_configuration_except_packets():
    ids = sorted(c.id for c in expand(accels=["bvh"], traversals=["packet", "single"], renderers={"simd_only": {}}))
    assert ids == ["random100-simd_only-optimized-bvh", "random100-simd_only-optimized-bvh-single"]


def test_the_default_is_packets_and_leaves_configuration_names_as_they_were():
    (config,) = expand(accels=["bvh"], renderers={"simd_tbb": {"threads": [2]}})
    assert config.traversal == names.PACKET
    assert config.id == "random100-simd_tbb-optimized-bvh-threads2"
    assert flag_value(config, configurations.TRAVERSAL_FLAG) == names.PACKET


def test_hybrid_thresholds_multiply_hybrid_only():
    configs = expand(
        accels=["bvh"], traversals=["packet", "hybrid"], hybrid_thresholds=[2, 6], renderers={"simd_only": {}}
    )
    assert sorted(c.id for c in configs) == [
        "random100-simd_only-optimized-bvh",
        "random100-simd_only-optimized-bvh-hybrid2",
        "random100-simd_only-optimized-bvh-hybrid6",
    ]
    for c in configs:
        threshold = flag_value(c, configurations.HYBRID_THRESHOLD_FLAG)
        assert threshold == (str(c.hybrid_threshold) if c.traversal == "hybrid" else None)
        assert c.describe()["hybrid_threshold"] == c.hybrid_threshold


def test_hybrid_without_thresholds_runs_the_kernels_default():
    (config,) = expand(accels=["bvh"], traversals=["hybrid"], renderers={"simd_only": {}})
    assert config.id.endswith("-bvh-hybrid") and configurations.HYBRID_THRESHOLD_FLAG not in argv(config)


def test_counters_reach_the_simd_kernel_and_the_gpu_renderer_only():
    configs = expand(accels=["none", "bvh"], counters=True, renderers=EVERY_RENDERER)
    counting = {c.renderer for c in configs if configurations.COUNTERS_FLAG in argv(c)}
    assert counting == {"simd_tbb", "simd_only", "gpu"}
    assert all(c.counters == (c.renderer in counting) for c in configs)
    assert not any(configurations.COUNTERS_FLAG in argv(c) for c in expand(renderers=EVERY_RENDERER))


def test_an_override_matches_traversals_and_never_a_configuration_without_one():
    configs = expand(
        accels=["none", "bvh"],
        traversals=["packet", "single"],
        renderers={"simd_tbb": {}, "simd_only": {}, "sequential": {}},
        overrides=[
            {"renderers": ["simd_only"], "traversals": ["single"], "skip": True},
            {"traversals": ["packet"], "frames": 9},
        ],
    )
    ids = {c.id: c for c in configs}
    assert "random100-simd_only-optimized-bvh-single" not in ids
    assert "random100-simd_tbb-optimized-bvh-single" in ids
    assert ids["random100-simd_tbb-optimized-bvh"].frames == 9
    assert ids["random100-sequential-optimized-bvh"].frames == profiles.TOP_RULES["frames"].default
    assert ids["random100-simd_tbb-optimized"].frames == profiles.TOP_RULES["frames"].default


@pytest.mark.parametrize(
    "keys, message",
    [
        ({"traversals": ["packet", "zigzag"]}, "traversals must be a list, each one of packet, single, hybrid"),
        ({"traversals": "single"}, "traversals must be a list"),
        ({"traversals": ["single", "single"]}, "traversals names a value twice"),
        (
            {"hybrid_thresholds": [4]},
            "hybrid_thresholds: applies to the simd_tbb and simd_only renderers with traversal hybrid only, and this "
            "profile has no traversal hybrid",
        ),
        ({"traversals": ["hybrid"], "hybrid_thresholds": [0]}, "each an integer >= 1"),
        ({"traversals": ["hybrid"], "hybrid_thresholds": ["4"]}, "hybrid_thresholds must be a list"),
        ({"counters": "yes"}, "counters must be true or false"),
        (
            {"accels": ["none"], "traversals": ["single"]},
            "traversals: applies to the simd_tbb and simd_only renderers with accel bvh only, and this profile has no "
            "accel bvh",
        ),
        ({"overrides": [{"traversals": ["fast"], "skip": True}]}, "overrides[0].traversals must be a list"),
    ],
)
def test_bad_traversal_and_counter_keys_name_the_file_and_key(keys, message):
    with pytest.raises(ProfileError, match=re.escape(message)) as e:
        profile(accels=keys.pop("accels", ["bvh"]), renderers={"simd_tbb": {}}, **keys)
    assert str(e.value).startswith(f"{PATH}: ")


@pytest.mark.parametrize(
    "keys, message",
    [
        (
            {"traversals": ["single"]},
            "traversals: applies to the simd_tbb and simd_only renderers only, which this profile does not run",
        ),
        (
            {"counters": True},
            "counters: applies to the simd_tbb, simd_only and gpu renderers only, which this profile does not run",
        ),
    ],
)
def test_traversals_and_counters_must_reach_a_renderer_that_takes_them(keys, message):
    with pytest.raises(ProfileError, match=re.escape(message)):
        profile(accels=["bvh"], renderers={"sequential": {}, "embree": {}}, **keys)


def test_the_counters_profile_runs_the_thesis_stages_with_counters_on_both_simd_renderers():
    p = profiles.load_profile("counters")
    configs = configurations.expand(p, [profiles.resolve_scene(s) for s in p.scenes], 2)
    assert {c.variant.label for c in configs} == set(names.STAGES)
    assert {c.renderer for c in configs} == {"simd_tbb", "simd_only"} and all(c.counters for c in configs)
    cells = {(c.scene, c.renderer, c.variant.label, c.accel, c.traversal) for c in configs}
    walks = [("none", ""), *(("bvh", t) for t in names.TRAVERSALS)]
    assert cells == {
        (scene, renderer, stage, accel, traversal)
        for scene in ("random100", "random1000")
        for renderer in ("simd_tbb", "simd_only")
        for stage in names.STAGES
        for accel, traversal in walks
    }
