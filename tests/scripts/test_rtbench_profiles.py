"""Profiles: the shipped ones are valid and describe the study; expansion,
overrides, interleaving and errors."""

import textwrap
from pathlib import Path

import pytest

from rtbench import configurations, names, profiles, scenes, schema
from rtbench.profiles import ProfileError

SHIPPED = sorted(p.stem for p in profiles.PROFILES_DIR.glob("*.toml"))


def _expand(name, cpu_count=2, **kw):
    profile = profiles.load_profile(name)
    scenes = [profiles.resolve_scene(s) for s in profile.scenes]
    return profile, configurations.expand(profile, scenes, cpu_count, **kw)


def test_the_required_profiles_exist():
    assert {"paper", "quick", "scaling", "tracy"} <= set(SHIPPED)


@pytest.mark.parametrize("name", SHIPPED)
def test_every_shipped_profile_loads_and_expands(name):
    profile, configs = _expand(name)
    assert configs and profile.description
    assert len({c.id for c in configs}) == len(configs)
    for c in configs:
        argv = c.argv(Path("rt"), Path("x.csv"), Path("x.meta.json"))
        assert argv[1] == names.RENDERER_FLAGS[c.renderer]
        assert argv[-5:] == ["--csv", "x.csv", "--meta", "x.meta.json", "--quiet"]


def test_paper_covers_the_thesis_tables():
    profile, configs = _expand("paper")
    cells = {(c.scene, c.renderer, c.variant.label) for c in configs}
    for scene in ("default", "random20", "random100"):
        for renderer in names.RENDERERS:
            for stage in names.STAGES:
                assert (scene, renderer, stage) in cells
    assert profile.repetitions >= 3 and profile.interleave != "blocked"
    sizes = {(c.width, c.height) for c in configs}
    assert len(sizes) == 1, "speedups must compare equal work: one image size"


def test_scaling_runs_every_thread_count_and_both_lane_widths():
    _, configs = _expand("scaling", cpu_count=4)
    threaded = [dict(c.axes) for c in configs if "threads" in dict(c.axes)]
    assert {a["threads"] for a in threaded} == {"1", "2", "3", "4"}
    assert {a.get("lanes") for a in threaded} >= {"4", "native"}


def test_threads_values():
    assert configurations.parse_threads("all", 6) == [6]
    assert configurations.parse_threads("2..all", 4) == [2, 3, 4]
    assert configurations.parse_threads(3, 4) == [3]
    with pytest.raises(ProfileError):
        configurations.parse_threads("zero", 4)


def test_overrides_change_frames_of_matching_cells_only():
    _, configs = _expand("paper")
    by_cell = {(c.renderer, c.variant.label, c.scene): c for c in configs}
    ref = names.reference_renderer()
    assert by_cell[(ref, "original", "random100")].frames < by_cell[(ref, "optimized", "random100")].frames


def test_forced_values_and_renderer_filter_win():
    _, configs = _expand("paper", renderers=[names.reference_renderer()], forced={"width": 32, "frames": 2})
    assert {c.renderer for c in configs} == {names.reference_renderer()}
    assert {(c.width, c.frames) for c in configs} == {(32, 2)}


def test_round_robin_alternates_renderers_and_shuffle_is_seeded():
    _, configs = _expand("quick")
    order = configurations.schedule(configs, 2, "round-robin", 1)
    assert [rep for rep, _ in order] == [0] * len(configs) + [1] * len(configs)
    firsts = [c.renderer for _, c in order[: len(names.RENDERERS)]]
    assert firsts == names.RENDERERS  # consecutive runs change renderer
    a = configurations.schedule(configs, 2, "shuffle", 5)
    assert a == configurations.schedule(configs, 2, "shuffle", 5)
    assert a != configurations.schedule(configs, 2, "shuffle", 6)
    assert sorted(c.id for _, c in a) == sorted(c.id for _, c in order)
    blocked = configurations.schedule(configs, 2, "blocked", 1)
    assert blocked[0][1] == blocked[1][1]


def test_explicit_algorithm_and_early_exits_become_their_own_variant(tmp_path):
    path = _write(
        tmp_path,
        """
        description = "ablation"
        scenes = ["default"]
        stages = ["optimized", {algorithm = "two-pass", early_exits = ["bounce"]},
                  {algorithm = "single-pass", early_exits = ["bounce"]}]
        [renderers.sequential]
    """,
    )
    variants = profiles.load_profile(str(path)).variants
    assert [v.label for v in variants] == ["optimized", "two-pass[bounce]", "single-pass"]
    assert variants[1].args() == ["--algorithm", "two-pass", "--early-exit", "bounce"]


def _write(tmp_path, text):
    path = tmp_path / "p.toml"
    path.write_text(textwrap.dedent(text))
    return path


# The keys every profile needs, before the part a case gets wrong.
PROFILE_HEAD = 'description = "x"\nscenes = ["default"]\nstages = ["optimized"]\n'


@pytest.mark.parametrize(
    "body, message",
    [
        (
            PROFILE_HEAD + "bogus = 1\n[renderers.sequential]\n",
            "bogus",
        ),
        ('description = "x"\nscenes = ["default"]\nstages = ["fast"]\n[renderers.sequential]\n', "fast"),
        (PROFILE_HEAD + "[renderers.turbo]\n", "turbo"),
        (
            PROFILE_HEAD + "frames = 0\n[renderers.sequential]\n",
            "frames",
        ),
        (PROFILE_HEAD + "[renderers.simd_tbb]\nwarp = [1]\n", "warp"),
        ('description = "x"\nstages = ["optimized"]\n[renderers.sequential]\n', "scenes"),
        ('description = "x"\nscenes = [\n', "TOML"),
        (
            PROFILE_HEAD + "[renderers.simd_only]\nlanes = [3]\n",
            "renderers.simd_only.lanes must be one of 4, 8, 16, native",
        ),
        (
            PROFILE_HEAD + '[renderers.simd_tbb]\npartition = "cols"\n',
            "renderers.simd_tbb.partition must be one of rows, tiles",
        ),
        (
            PROFILE_HEAD + '[renderers.tbb_only]\nthreads = ["many"]\n',
            "renderers.tbb_only.threads must be a positive integer",
        ),
        (
            PROFILE_HEAD + 'interleave = "random"\n[renderers.gpu]\n',
            "interleave must be one of round-robin, shuffle, blocked, not 'random'",
        ),
        (
            PROFILE_HEAD + 'architecture = "arm"\n[renderers.sequential]\n',
            "architecture must be one of , x86_64, aarch64, not 'arm'",
        ),
    ],
)
def test_bad_profiles_are_rejected_naming_file_and_key(tmp_path, body, message):
    path = tmp_path / "bad.toml"
    path.write_text(body)
    with pytest.raises(ProfileError) as e:
        profiles.load_profile(str(path))
    assert str(path) in str(e.value) and message in str(e.value)


def test_scenes_by_name_or_path(tmp_path):
    assert profiles.resolve_scene("random20") == (profiles.SCENES_DIR / "random20.json").resolve()
    own = tmp_path / "mine.json"
    own.write_text("{}")
    assert profiles.resolve_scene(str(own)) == own.resolve()
    with pytest.raises(ProfileError, match="nosuch"):
        profiles.resolve_scene("nosuch")
    with pytest.raises(ProfileError, match="no profile 'nosuch'"):
        profiles.load_profile("nosuch")


OPTION_VALUES = {"threads": 2, "lanes": names.LANE_WIDTHS[0], "grain": 4, "partition": names.PARTITIONS[-1]}


@pytest.mark.parametrize("renderer", names.RENDERERS)
@pytest.mark.parametrize("option", names.OPTION_FLAGS)
def test_a_renderer_takes_exactly_the_options_the_schema_gives_it(tmp_path, renderer, option):
    value = OPTION_VALUES.get(option, 1)
    path = _write(
        tmp_path,
        f"""
        description = "x"
        scenes = ["default"]
        stages = ["optimized"]
        [renderers.{renderer}]
        {option} = [{value!r}]
    """.replace("'", '"'),
    )
    if option not in schema.accepted_options(renderer):
        with pytest.raises(ProfileError, match=f"renderers.{renderer}.{option}: renderer {renderer} does not take"):
            profiles.load_profile(str(path))
        return
    profile = profiles.load_profile(str(path))
    (config,) = configurations.expand(profile, [profiles.resolve_scene("default")], cpu_count=2)
    argv = config.argv(Path("rt"), Path("x.csv"), Path("x.meta.json"))
    flag = schema.renderer_options()[option]
    assert argv[argv.index(flag) + 1] == str(value)


def test_accels_are_an_axis_passed_as_accel(tmp_path):
    default = profiles.load_profile(
        str(
            _write(
                tmp_path,
                """
        description = "x"
        scenes = ["default"]
        stages = ["optimized"]
        [renderers.sequential]
    """,
            )
        )
    )
    assert default.accels == (names.BRUTE_FORCE,)
    path = _write(
        tmp_path,
        f"""
        description = "x"
        scenes = ["default"]
        stages = ["optimized"]
        accels = {list(names.RUN_ACCELS)!r}
        [renderers.sequential]
        [[overrides]]
        accels = [{names.RUN_ACCELS[-1]!r}]
        frames = 9
    """.replace("'", '"'),
    )
    configs = configurations.expand(profiles.load_profile(str(path)), [profiles.resolve_scene("default")], cpu_count=2)
    assert [c.accel for c in configs] == names.RUN_ACCELS
    assert len({c.id for c in configs}) == len(configs)
    for c in configs:
        argv = c.argv(Path("rt"), Path("x.csv"), Path("x.meta.json"))
        assert argv[argv.index(configurations.ACCEL_FLAG) + 1] == c.accel
        assert c.describe()["accel"] == c.accel
        assert c.frames == (9 if c.accel == names.RUN_ACCELS[-1] else 5)  # overrides match on accels


def test_a_renderer_with_its_own_structure_runs_once_with_it(tmp_path):
    (own, accel), *_ = names.OWN_ACCEL.items()
    path = _write(
        tmp_path,
        f"""
        description = "x"
        scenes = ["default"]
        stages = ["optimized"]
        accels = {list(names.RUN_ACCELS)!r}
        [renderers.{own}]
        [renderers.sequential]
    """.replace("'", '"'),
    )
    configs = configurations.expand(profiles.load_profile(str(path)), [profiles.resolve_scene("default")], cpu_count=2)
    assert [c.accel for c in configs if c.renderer == own] == [accel]
    assert sorted(c.accel for c in configs if c.renderer == "sequential") == sorted(names.RUN_ACCELS)


def test_an_unknown_accel_is_rejected_naming_the_schemas(tmp_path):
    path = _write(
        tmp_path,
        """
        description = "x"
        scenes = ["default"]
        stages = ["optimized"]
        accels = ["kd-tree"]
        [renderers.sequential]
    """,
    )
    with pytest.raises(ProfileError, match=f"accels must be a list, each one of {', '.join(names.RUN_ACCELS)}"):
        profiles.load_profile(str(path))


def test_a_scene_the_generator_makes_resolves_into_the_run_directory():
    assert profiles.resolve_scene("random7") == profiles.GENERATED_SCENES / "random7.json"
    assert profiles.resolve_scene("crowd70") == profiles.GENERATED_SCENES / "crowd70.json"
    with pytest.raises(ProfileError, match="randomN and groundN, clustersN"):
        profiles.resolve_scene("random0")


def _spheres(config):
    return int(config.scene.removeprefix(scenes.family_of(config.scene)))


def test_scene_size_fits_every_renderer_and_accel_on_three_counts_and_keeps_slow_cells_small():
    profile, configs = _expand("scene-size")
    uniform = [c for c in configs if scenes.family_of(c.scene) == "random"]
    assert {_spheres(c) for c in uniform} == {10, 100, 1000, 10000, 100000, 1000000}
    # The corpus beside them: each family at its committed size and at 10000, generated there.
    corpus = {c.scene for c in configs} - {c.scene for c in uniform}
    assert corpus == {*scenes.CORPUS, *(f"{family}10000" for family in scenes.CORPUS_FAMILIES)}
    for c in configs:
        if c.scene in scenes.CORPUS:
            assert c.scene_path == str((profiles.SCENES_DIR / f"{c.scene}.json").resolve())
        elif c.scene in corpus:
            assert c.scene_path.startswith(str(profiles.GENERATED_SCENES))
            assert names.accepts(c.renderer, "lanes") or c.renderer in names.OWN_ACCEL or c.renderer == "gpu"
    assert {c.variant.label for c in configs} == {"optimized"} and {(c.width, c.height) for c in configs} == {
        (800, 600)
    }
    for renderer in profile.renderers:
        for accel in [names.OWN_ACCEL[renderer]] if renderer in names.OWN_ACCEL else names.RUN_ACCELS:
            counts = {_spheres(c) for c in uniform if c.renderer == renderer and c.accel == accel}
            assert len(counts) >= 3, (renderer, accel)
            if (
                not names.accepts(renderer, "lanes")
                and names.renders_on_cpu(renderer)
                and renderer not in names.OWN_ACCEL
            ):
                assert max(counts) <= 1000, f"scalar {renderer} stays at small N"
    for n in (100000, 1000000):
        largest = [
            (c.renderer, c.accel, c.traversal or "/".join(filter(None, c.gpu_axes.values())))
            for c in configs
            if _spheres(c) == n
        ]
        every_traversal = [("simd_tbb", "bvh", t) for t in names.TRAVERSALS]
        every_gpu_variant = [("gpu", "bvh", b) for b in names.GPU_BVHS]
        gpu_rt = ("gpu_rt", "bvh", "none")  # on the driver's structure, without reordering
        assert sorted(largest) == sorted([("embree", "bvh", ""), gpu_rt, *every_gpu_variant, *every_traversal]), n
    # The traversal axis: simd_tbb's BVH at every count, simd_only's in packets only.
    for renderer, walks in (("simd_tbb", set(names.TRAVERSALS)), ("simd_only", {names.PACKET})):
        assert {c.traversal for c in configs if c.renderer == renderer and c.accel == "bvh"} == walks
    generated = (10, 100000, 1000000)
    assert all(c.scene_path.startswith(str(profiles.GENERATED_SCENES)) for c in configs if _spheres(c) in generated)


def test_the_thesis_neon_profiles_are_for_aarch64_at_four_lanes_on_both_optimisation_levels():
    optimised, unoptimised = profiles.load_profile("thesis-neon"), profiles.load_profile("thesis-neon-o0")
    assert (optimised.preset, unoptimised.preset) == ("release", "paper-o0")
    for p in (optimised, unoptimised):
        assert p.architecture == "aarch64"
        assert [v.label for v in p.variants] == ["original", "single-pass", "optimized"]
        assert {r: p.renderers[r]["lanes"] for r in ("simd_tbb", "simd_only")} == {"simd_tbb": [4], "simd_only": [4]}


def test_bench_refuses_a_profile_written_for_another_architecture(tmp_path, repo_root):
    from rtbench import bench, emulation

    other = "x86_64" if emulation.host_architecture() == "aarch64" else "aarch64"
    path = _write(tmp_path, PROFILE_HEAD + f'architecture = "{other}"\n[renderers.sequential]\n')
    with pytest.raises(ProfileError, match=f"architecture = '{other}', and this machine is"):
        bench.plan(bench.parse_args(["--profile", str(path), "--dry-run"], "bench"))
