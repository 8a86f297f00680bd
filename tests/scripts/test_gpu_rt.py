"""The gpu_rt renderer (the Vulkan ray-tracing pipeline) in rtbench: its
reorder axis in profiles (gpu_rt_reorders, --gpu-rt-reorder) and in the
frame CSV (gpu_rt_reorder, for gpu_rt rows only), the bench's probe per
reorder value (a fake binary that lacks the reorder extension, or the
ray-tracing pipeline altogether), the report's note on the skipped runs, and
its gpu_ms beside the gpu renderer's."""

from __future__ import annotations

import csv
import io
import json
import re
import statistics
import textwrap
from collections import Counter
from pathlib import Path

import profile_test_support as support
import pytest
from profile_test_support import argv, flag_value
from synthetic_runs import SyntheticConfig, table_rows, write_run_dir

from rtbench import bench, configurations, load, manifests, names, profiles, report_writer
from rtbench.profiles import ProfileError
from rtbench.run_status import RunStatus

PATH = Path("gpu-rt-test.toml")
# Hand-written: the schema's reorder values and the flag the raytracer takes for them.
REORDERS = ["none", "hit"]
FLAG = "--gpu-rt-reorder"


def profile(**keys):
    return support.profile(PATH, **keys)


def expand(**keys):
    return support.expand(PATH, **keys)


def test_the_schema_lists_the_reorders_this_test_knows():
    assert names.GPU_RT_REORDERS == REORDERS
    assert configurations.GPU_FLAGS[names.GPU_RT_REORDER] == FLAG
    assert names.GPU_RT_RENDERER in names.GPU_MS_RENDERERS and names.GPU_RENDERER in names.GPU_MS_RENDERERS


# --- profiles ---------------------------------------------------------------------


def test_the_reorders_multiply_gpu_rt_only_and_reach_its_command_line():
    configs = expand(
        accels=["none", "bvh"],
        renderers={"gpu_rt": {}, "gpu": {}, "simd_tbb": {}},
        gpu_rt_reorders=REORDERS,
    )
    rt = [c for c in configs if c.renderer == "gpu_rt"]
    # Its own structure: once per scene and stage whatever the accels, then once per reorder.
    assert sorted(c.gpu_rt_reorder for c in rt) == sorted(REORDERS)
    assert {c.accel for c in rt} == {"bvh"}
    for c in rt:
        assert flag_value(c, FLAG) == c.gpu_rt_reorder
        assert c.describe()["gpu_rt_reorder"] == c.gpu_rt_reorder
        # The compute renderer's axes do not reach it.
        assert not any(flag_value(c, f) for f in ("--gpu-bvh", "--gpu-schedule", "--gpu-path"))
    for c in configs:
        if c.renderer != "gpu_rt":
            assert c.gpu_rt_reorder == "" and FLAG not in argv(c), c.id
    assert {c.id for c in rt} == {"random100-gpu_rt-optimized-bvh", "random100-gpu_rt-optimized-bvh-hit-reorder"}


def test_the_default_runs_gpu_rt_without_reordering():
    (config,) = expand(renderers={"gpu_rt": {}})
    assert config.gpu_rt_reorder == "none" and flag_value(config, FLAG) == "none"
    assert config.id == "random100-gpu_rt-optimized-bvh"


def test_an_override_matches_the_reorder_and_never_another_renderer():
    configs = expand(
        renderers={"gpu_rt": {}, "gpu": {}},
        gpu_rt_reorders=REORDERS,
        overrides=[{"gpu_rt_reorders": ["hit"], "frames": 9}],
    )
    frames = {c.id: c.frames for c in configs}
    default = profiles.TOP_RULES["frames"].default
    assert frames == {
        "random100-gpu-optimized": default,
        "random100-gpu_rt-optimized-bvh": default,
        "random100-gpu_rt-optimized-bvh-hit-reorder": 9,
    }


@pytest.mark.parametrize(
    "keys, message",
    [
        ({"gpu_rt_reorders": ["none", "sort"]}, "gpu_rt_reorders must be a list, each one of none, hit"),
        ({"gpu_rt_reorders": "hit"}, "gpu_rt_reorders must be a list"),
        ({"gpu_rt_reorders": ["hit", "hit"]}, "gpu_rt_reorders names a value twice"),
        ({"overrides": [{"gpu_rt_reorders": ["sort"], "skip": True}]}, "overrides[0].gpu_rt_reorders must be a list"),
    ],
)
def test_bad_reorder_keys_name_the_file_and_key(keys, message):
    with pytest.raises(ProfileError, match=re.escape(message)) as e:
        profile(renderers={"gpu_rt": {}}, **keys)
    assert str(e.value).startswith(f"{PATH}: ")


@pytest.mark.parametrize("reorders", [["hit"], ["none", "hit"]])
def test_a_reorder_besides_none_needs_the_gpu_rt_renderer(reorders):
    # The gpu renderer is not enough: the axis belongs to gpu_rt.
    with pytest.raises(ProfileError, match=re.escape("gpu_rt_reorders: applies to the gpu_rt renderer only")):
        profile(accels=["bvh"], renderers={"gpu": {}, "simd_tbb": {}}, gpu_rt_reorders=reorders)
    # The default alone is what every profile says without the key: no error.
    profile(accels=["bvh"], renderers={"gpu": {}}, gpu_rt_reorders=["none"])


def test_the_gpu_machine_profile_runs_gpu_rt_as_the_gpu_and_hit_reordering_on_random100():
    p = profiles.load_profile("gpu-machine")
    configs = configurations.expand(p, [profiles.resolve_scene(s) for s in p.scenes], 16)
    rt = [c for c in configs if c.renderer == "gpu_rt"]
    cells = Counter((c.scene, c.variant.label, (c.width, c.height), c.gpu_rt_reorder) for c in rt)
    sizes = ((800, 600), (1920, 1080))
    expected = {(scene, stage, size, "none"): 1 for scene in p.scenes for stage in names.STAGES for size in sizes}
    expected.update({("random100", stage, size, "hit"): 1 for stage in names.STAGES for size in sizes})
    assert cells == expected
    # As the gpu renderer's runs: warm-up and measured frames.
    gpu_frames = {(c.warmup, c.frames) for c in configs if c.renderer == "gpu"}
    assert {(c.warmup, c.frames) for c in rt} == gpu_frames == {(2, 40)}


# --- the frame CSV ------------------------------------------------------------------

TIMES = [[3.0, 1.0, 1.1, 1.2]]
RT = SyntheticConfig(renderer="gpu_rt", threads=0, lanes=0, accel="bvh", gpu_rt_reorder="none")
RT_HIT = SyntheticConfig(renderer="gpu_rt", threads=0, lanes=0, accel="bvh", gpu_rt_reorder="hit")
GPU = SyntheticConfig(renderer="gpu", threads=0, lanes=0, accel="bvh", gpu_bvh="binary", gpu_schedule="pixel")
SIMD = SyntheticConfig(accel="bvh", traversal="packet")


def _rewrite(path: Path, column: str, value: str) -> None:
    rows = list(csv.DictReader(io.StringIO(path.read_text())))
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=list(rows[0]), lineterminator="\n")
    writer.writeheader()
    for row in rows:
        row[column] = value
        writer.writerow(row)
    path.write_text(out.getvalue())


def test_the_reorder_column_loads_as_written_and_names_configurations_apart(tmp_path):
    write_run_dir(tmp_path, {RT: TIMES, RT_HIT: TIMES, GPU: TIMES})
    frames = load.load_runs([tmp_path])
    by_renderer = {r: set(frames.loc[frames[names.RENDERER] == r, names.GPU_RT_REORDER]) for r in ("gpu", "gpu_rt")}
    assert by_renderer == {"gpu": {""}, "gpu_rt": {"none", "hit"}}
    assert frames.groupby(names.CONFIG_KEYS, dropna=False).ngroups == 3


def test_a_gpu_rt_row_without_the_reorder_ran_none(tmp_path):
    write_run_dir(tmp_path, {RT: TIMES})
    (path,) = tmp_path.glob("frames/*.csv")
    _rewrite(path, names.GPU_RT_REORDER, "")
    frames = load.load_runs([tmp_path])
    assert set(frames[names.GPU_RT_REORDER]) == {"none"}


@pytest.mark.parametrize(
    "config, value, message",
    [
        (
            GPU,
            "none",
            "line 2: column gpu_rt_reorder: none with renderer gpu, accel bvh (applies to the gpu_rt renderer only)",
        ),
        (
            SIMD,
            "hit",
            "line 2: column gpu_rt_reorder: hit with renderer simd_tbb, accel bvh "
            "(applies to the gpu_rt renderer only)",
        ),
        (RT, "sorted", "column gpu_rt_reorder: unknown value 'sorted'"),
        (RT, "Hit", "column gpu_rt_reorder: unknown value 'Hit'"),
    ],
)
def test_a_reorder_that_cannot_be_right_names_the_file(tmp_path, config, value, message):
    write_run_dir(tmp_path, {config: TIMES})
    (path,) = tmp_path.glob("frames/*.csv")
    _rewrite(path, names.GPU_RT_REORDER, value)
    with pytest.raises(load.RunDataError) as e:
        load.load_runs([tmp_path])
    assert str(e.value).startswith(str(path)) and message in str(e.value)


def test_the_compute_axes_on_a_gpu_rt_row_are_refused(tmp_path):
    write_run_dir(tmp_path, {RT: TIMES})
    (path,) = tmp_path.glob("frames/*.csv")
    _rewrite(path, names.GPU_PATH, "megakernel")
    with pytest.raises(load.RunDataError, match=re.escape("applies to the gpu renderer only")):
        load.load_runs([tmp_path])


# --- the probe ----------------------------------------------------------------------

NO_REORDER = (
    "raytracer: no usable Vulkan device: device 0 (NVIDIA Test) offers no VK_NV_ray_tracing_invocation_reorder: "
    "--gpu-rt-reorder hit needs it"
)
# As long as the binary's message (over 200 characters), so that a reason cut to its tail would lose its start.
NO_RT = (
    "raytracer: no usable Vulkan device: device 0 (llvmpipe (LLVM 15.0.6, 256 bits)) offers no "
    "VK_KHR_acceleration_structure / VK_KHR_ray_tracing_pipeline: the gpu_rt renderer needs them "
    "(a GPU with ray-tracing support and its vendor's driver)"
)
# What a probe records where the binary printed something before its error (usage, warnings).
BEFORE_THE_ERROR = "Usage: raytracer [OPTIONS] SCENE\n  --gpu-rt  the ray-tracing pipeline\n"


def fake_binary(tmp_path: Path, refuse: str) -> Path:
    """A stand-in raytracer: exits 3 with the message of a device that lacks
    the reorder extension (refuse 'hit': only for --gpu-rt-reorder hit) or
    the ray-tracing pipeline (refuse 'gpu_rt': for every --gpu-rt); anything
    else succeeds. Each call appends its arguments to calls.log."""
    path = tmp_path / "raytracer"
    path.write_text(
        textwrap.dedent(
            f"""\
            #!/bin/sh
            echo "$*" >> "{tmp_path / "calls.log"}"
            case " $* " in
              *" --gpu-rt "*) rt=1 ;;
              *) rt=0 ;;
            esac
            case " $* " in
              *" --gpu-rt-reorder hit "*) hit=1 ;;
              *) hit=0 ;;
            esac
            if [ "{refuse}" = gpu_rt ] && [ $rt = 1 ]; then echo "{NO_RT}" >&2; exit 3; fi
            if [ "{refuse}" = hit ] && [ $hit = 1 ]; then echo "{NO_REORDER}" >&2; exit 3; fi
            exit 0
            """
        )
    )
    path.chmod(0o755)
    return path


def manifest_of(tmp_path: Path, binary: Path) -> manifests.Manifest:
    p = profile(renderers={"gpu_rt": {}, "simd_tbb": {}}, gpu_rt_reorders=REORDERS)
    configs = configurations.expand(p, [Path("scenes/random100.json").resolve()], 2)
    order = configurations.schedule(configs, 2, "round-robin", 1)
    runs = manifests.plan_runs(order, binary, tmp_path)
    return manifests.Manifest(
        profile={"name": "test"},
        configs=[c.describe() for c in configs],
        runs=runs,
        binary=str(binary),
        command_line=[],
        host={},
    )


def test_the_probe_tries_each_reorder_and_skips_only_the_runs_the_device_lacks(tmp_path):
    binary = fake_binary(tmp_path, refuse="hit")
    manifest = manifest_of(tmp_path, binary)
    out = io.StringIO()
    bench.mark_unavailable(manifest, binary, tmp_path, out)
    status = {(r.config, r.repetition): r.status for r in manifest.runs}
    hit = "random100-gpu_rt-optimized-bvh-hit-reorder"
    for (config, _), s in status.items():
        assert s == (RunStatus.UNAVAILABLE if config == hit else RunStatus.PENDING), config
    assert all("VK_NV_ray_tracing_invocation_reorder" in r.stderr_tail for r in manifest.runs if r.config == hit)
    assert out.getvalue().startswith("bench: skipping gpu_rt --gpu-rt-reorder hit: ")
    # Three probes: simd_tbb, gpu_rt without reordering, gpu_rt with hit reordering.
    calls = (tmp_path / "calls.log").read_text().splitlines()
    assert len(calls) == 3
    assert sum("--gpu-rt-reorder hit" in c for c in calls) == 1 and sum("--gpu-rt" in c.split() for c in calls) == 2


def test_a_device_without_the_ray_tracing_pipeline_skips_every_gpu_rt_run(tmp_path):
    binary = fake_binary(tmp_path, refuse="gpu_rt")
    manifest = manifest_of(tmp_path, binary)
    bench.mark_unavailable(manifest, binary, tmp_path, io.StringIO())
    for r in manifest.runs:
        assert r.status == (RunStatus.UNAVAILABLE if r.renderer == "gpu_rt" else RunStatus.PENDING), r.config
        if r.renderer == "gpu_rt":
            assert r.stderr_tail.startswith("exit 3: ") and "VK_KHR_ray_tracing_pipeline" in r.stderr_tail


# --- the report ---------------------------------------------------------------------

SEQUENTIAL = SyntheticConfig(renderer="sequential", threads=1, lanes=1)


def run_with_skipped_gpu_rt(run: Path, hit_only: bool) -> Path:
    """A run directory whose sequential runs ran and whose gpu_rt runs (all,
    or the hit-reorder ones only) the probe skipped, as the bench records them."""
    write_run_dir(run, {SEQUENTIAL: TIMES * 2, **({RT: TIMES * 2} if hit_only else {})})
    manifest = json.loads((run / load.MANIFEST).read_text())
    skipped = {"random20-gpu_rt-optimized-bvh-hit-reorder": ("hit", NO_REORDER)}
    if not hit_only:
        skipped["random20-gpu_rt-optimized-bvh"] = ("none", NO_RT)
        skipped["random20-gpu_rt-optimized-bvh-hit-reorder"] = ("hit", NO_RT)
    manifest["configs"] = [
        {"id": config, "renderer": "gpu_rt", "gpu_rt_reorder": v} for config, (v, _) in skipped.items()
    ]
    for config, (_, message) in skipped.items():
        for rep in range(2):
            manifest["runs"].append(
                {
                    "config": config,
                    "repetition": rep,
                    "renderer": "gpu_rt",
                    "csv": f"frames/{config}-r{rep}.csv",
                    "meta": f"frames/{config}-r{rep}.meta.json",
                    "status": RunStatus.UNAVAILABLE,
                    "stderr_tail": f"exit 3: {BEFORE_THE_ERROR}{message}",
                }
            )
    (run / load.MANIFEST).write_text(json.dumps(manifest))
    return run


def _skipped_rows(readme: str) -> list[list[str]]:
    section = readme.split("## Runs without data", 1)[1].split("\n## ", 1)[0]
    return [r for r in table_rows(section) if "skipped" in r[1]]


def test_the_report_says_gpu_rt_was_skipped_and_why(tmp_path):
    run = run_with_skipped_gpu_rt(tmp_path / "run", hit_only=False)
    assert report_writer.main([str(run), "-o", str(tmp_path / "report"), "-q"]) == 0
    readme = (tmp_path / "report/README.md").read_text()
    (row,) = _skipped_rows(readme)
    assert row[0] == "every gpu_rt run (4)" and row[1] == "skipped: its probe failed"
    # The probe's exit status and its error whole, without what the binary printed before it.
    assert len(NO_RT) > 200 and row[3] == f"exit 3: {NO_RT}"
    assert "in this binary" not in readme
    assert "VK_NV_ray_tracing_invocation_reorder" in readme.split("## Runs without data", 1)[1]


def test_the_report_names_the_reorder_whose_runs_were_skipped(tmp_path):
    run = run_with_skipped_gpu_rt(tmp_path / "run", hit_only=True)
    assert report_writer.main([str(run), "-o", str(tmp_path / "report"), "-q"]) == 0
    (row,) = _skipped_rows((tmp_path / "report/README.md").read_text())
    assert row[0] == "every gpu_rt run with `--gpu-rt-reorder hit` (2)"
    assert row[3] == f"exit 3: {NO_REORDER}"


# --- gpu_ms beside the gpu renderer's ---------------------------------------------------

GPU_AT = {
    scene: SyntheticConfig(
        scene=scene,
        renderer="gpu",
        threads=0,
        lanes=0,
        accel="bvh",
        gpu_bvh="binary",
        gpu_schedule="pixel",
        gpu_path="megakernel",
    )
    for scene in ("random20", "random100")
}
RT_AT = {
    scene: SyntheticConfig(scene=scene, renderer="gpu_rt", threads=0, lanes=0, accel="bvh", gpu_rt_reorder="none")
    for scene in ("random20", "random100")
}
RT_HIT_100 = SyntheticConfig(
    scene="random100", renderer="gpu_rt", threads=0, lanes=0, accel="bvh", gpu_rt_reorder="hit"
)
GPU_MS = {
    GPU_AT["random20"]: [1.0, 0.8, 0.9, 1.0],
    GPU_AT["random100"]: [2.0, 1.6, 1.8, 2.0],
    RT_AT["random20"]: [1.0, 0.2, 0.3, 0.4],
    RT_AT["random100"]: [1.0, 0.4, 0.5, 0.6],
    RT_HIT_100: [1.0, 0.2, 0.25, 0.3],
}


def test_the_gpu_table_sets_gpu_rt_beside_the_gpu_at_each_scene(tmp_path):
    run = write_run_dir(
        tmp_path / "run",
        {config: [[3.0, 2.0, 2.1, 2.2]] for config in GPU_MS},
        counters={config: {"gpu_ms": ms} for config, ms in GPU_MS.items()},
    )
    assert report_writer.main([str(run), "-o", str(tmp_path / "report"), "-q"]) == 0
    table = (tmp_path / "report/tables/gpu-variants.md").read_text()
    header = [h.strip() for h in table.splitlines()[2].strip("|").split("|")]
    assert header[:3] == ["stage", "scene", "renderer"] and "reorder" in header and header[-1] == "× gpu"
    rows = [dict(zip(header, r)) for r in table_rows(table)]
    # Each scene: the gpu, then gpu_rt beside it.
    assert [(r["scene"], r["renderer"], r["reorder"]) for r in rows] == [
        ("random100", "gpu", "–"),
        ("random100", "gpu_rt", "none"),
        ("random100", "gpu_rt", "hit"),
        ("random20", "gpu", "–"),
        ("random20", "gpu_rt", "none"),
    ]

    def median(config):
        return statistics.median(GPU_MS[config][1:])

    for r in rows:
        if r["renderer"] != "gpu_rt":
            assert r["× gpu"] == "–"
            continue
        config = RT_HIT_100 if r["reorder"] == "hit" else RT_AT[r["scene"]]
        assert float(r["gpu_ms"]) == pytest.approx(median(config), abs=1e-3)
        assert float(r["× gpu"]) == pytest.approx(median(GPU_AT[r["scene"]]) / median(config), abs=0.006)
        assert float(r["× default"]) == pytest.approx(median(RT_AT[r["scene"]]) / median(config), abs=0.006)
