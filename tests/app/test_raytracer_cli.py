"""End-to-end checks of the raytracer binary: outputs, schema, exit codes."""

import csv
import hashlib
import json
import os
import re
import stat
import subprocess
from pathlib import Path

import pytest

from rtbench import schema

SMALL = ["--width", "24", "--height", "16", "--warmup", "2", "--frames", "3", "--quiet"]


def run(raytracer, *args, cwd=None):
    return subprocess.run([raytracer, *map(str, args)], capture_output=True, text=True, cwd=cwd)


def test_csv_and_metadata_follow_the_schema(raytracer, repo_root, tmp_path):
    csv_path = tmp_path / "run.csv"
    done = run(raytracer, "--sequential", repo_root / "scenes/random20.json", *SMALL, "--csv", csv_path)
    assert done.returncode == 0, done.stderr
    with csv_path.open(newline="") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0].keys()) == schema.frame_csv_columns()
    assert [int(r["frame"]) for r in rows] == [0, 1, 2, 3, 4]
    assert [r["warmup"] for r in rows] == ["1", "1", "0", "0", "0"]
    assert {r["renderer"] for r in rows} == {"sequential"}
    assert {r["scene"] for r in rows} == {"random20"}
    assert all(float(r["render_ms"]) > 0 for r in rows)
    assert all(r["gpu_ms"] == "" for r in rows)

    meta = json.loads((tmp_path / "run.meta.json").read_text())
    assert set(meta) == set(schema.run_metadata_keys())
    assert meta["run_id"] == rows[0]["run_id"]
    assert meta["schema_version"] == schema.schema()["version"]
    assert meta["scene"]["spheres"] == 20
    assert meta["scene"]["sha256"] == hashlib.sha256((repo_root / "scenes/random20.json").read_bytes()).hexdigest()
    assert meta["config"]["measured_frames"] == 3 and meta["config"]["warmup_frames"] == 2
    assert meta["started_at"].endswith("Z") and "T" in meta["started_at"]
    assert meta["command_line"][1] == "--sequential"
    assert not list(tmp_path.glob("*.tmp*")), "temporary files left behind"


# Runs that fill every metadata object a run without a window can write:
# scene, config, build (with build.nix), host, outputs (with saved frames),
# accel_structure, device. The window object: tests/window.
@pytest.mark.parametrize(
    "args, filled",
    [(["--sequential", "--accel", "bvh", "--present", "none"], "accel_structure"), (["--gpu"], "device")],
)
def test_every_nested_metadata_key_is_in_the_schema_and_written(raytracer, repo_root, tmp_path, args, filled):
    env = {**os.environ, "RT_NIX": "1", "RT_NIXPKGS_REV": "0" * 40}
    done = subprocess.run(
        [
            str(a)
            for a in [
                raytracer,
                *args,
                repo_root / "scenes/random20.json",
                *SMALL,
                "--csv",
                tmp_path / "run.csv",
                "--save-frame",
                f"1:{tmp_path / 'f1.png'}",
            ]
        ],
        capture_output=True,
        text=True,
        env=env,
    )
    assert done.returncode == 0, done.stderr
    meta = json.loads((tmp_path / "run.meta.json").read_text())
    assert meta[filled] is not None and meta["build"]["nix"] is not None and meta["outputs"]["frames"]
    assert schema.metadata_key_problems(meta) == []


def test_explicit_meta_path_and_saved_frames(raytracer, repo_root, tmp_path):
    done = run(
        raytracer,
        repo_root / "scenes/default.json",
        *SMALL,
        "--meta",
        tmp_path / "m.json",
        "--save-frame",
        f"0:{tmp_path / 'f0.png'}",
        "--save-frame",
        f"4:{tmp_path / 'f4.png'}",
    )
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "m.json").is_file()
    for name in ("f0.png", "f4.png"):
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert (tmp_path / "f0.png").read_bytes() != (tmp_path / "f4.png").read_bytes()  # the camera orbits


def test_summary_is_printed_unless_quiet(raytracer, repo_root):
    done = run(raytracer, repo_root / "scenes/default.json", "--width", "16", "--height", "8", "--frames", "2")
    assert done.returncode == 0
    assert "render_ms" in done.stdout and "median" in done.stdout


@pytest.mark.parametrize(
    "edit, path",
    [
        (lambda s: s["spheres"][1].update(radius=-1), "spheres[1].radius"),
        (lambda s: s["camera"].update(fov=180), "camera.fov"),
        (lambda s: s.update(extra=1), "extra"),
        (lambda s: s["render"].update(maxDepth=0), "render.maxDepth"),
    ],
)
def test_bad_scene_exits_2_naming_file_and_field_and_writes_nothing(raytracer, repo_root, tmp_path, edit, path):
    scene = json.loads((repo_root / "scenes/default.json").read_text())
    edit(scene)
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(scene))
    out = tmp_path / "out"
    out.mkdir()
    done = run(raytracer, bad, *SMALL, "--csv", out / "run.csv", "--save-frame", f"0:{out / 'f.png'}")
    assert done.returncode == 2
    assert str(bad) in done.stderr and path in done.stderr
    assert list(out.iterdir()) == []


def test_malformed_json_exits_2(raytracer, tmp_path):
    bad = tmp_path / "broken.json"
    bad.write_text('{"camera": [}')
    done = run(raytracer, bad, *SMALL)
    assert done.returncode == 2
    assert "broken.json" in done.stderr and "line 1" in done.stderr


def test_a_scene_file_over_the_size_limit_is_refused_unread(raytracer, tmp_path):
    huge = tmp_path / "huge.json"
    with huge.open("wb") as f:
        f.truncate((1 << 30) + 1)  # sparse: nothing is written, nor read
    done = run(raytracer, huge, *SMALL)
    assert done.returncode == 2
    assert "huge.json" in done.stderr and "larger than 1024 MiB" in done.stderr


def test_missing_scene_file_exits_2(raytracer, tmp_path):
    done = run(raytracer, tmp_path / "nope.json", *SMALL)
    assert done.returncode == 2
    assert "nope.json" in done.stderr


@pytest.mark.parametrize("name", schema.renderer_names())
def test_every_schema_renderer_runs_under_its_flag(raytracer, repo_root, name, tmp_path):
    flag = schema.renderer_flags()[name]
    csv_path = tmp_path / "x.csv"
    done = run(raytracer, flag, repo_root / "scenes/default.json", *SMALL, "--csv", csv_path)
    if done.returncode == 2 and "is not built in this version" in done.stderr:
        pytest.skip(f"{name} is not built in this binary (an optional dependency)")
    if done.returncode == 3 and "cannot run the ray-tracing pipeline renderer" in done.stderr:
        # tests/gpu/test_gpu_cli.py checks this refusal against what vulkaninfo says the device offers.
        pytest.skip(f"{name}: this Vulkan device has no ray-tracing pipeline (Debian 12's lavapipe)")
    assert done.returncode == 0, done.stderr
    with csv_path.open(newline="") as f:
        assert {r["renderer"] for r in csv.DictReader(f)} == {name}


@pytest.mark.parametrize("args", [["--width", "0"], ["--early-exit", "bogus"], ["--stage", "x"], ["--frames", "-1"]])
def test_bad_values_exit_2_with_usage(raytracer, args):
    done = run(raytracer, *args)
    assert done.returncode == 2
    assert "Usage" in done.stderr


def test_default_scene_is_found_from_the_repository_root(raytracer, repo_root):
    done = run(raytracer, "--width", "8", "--height", "8", "--frames", "1", "--warmup", "0", "--quiet", cwd=repo_root)
    assert done.returncode == 0, done.stderr


def test_help_and_version(raytracer):
    assert "--save-frame" in run(raytracer, "--help").stdout
    version = run(raytracer, "--version")
    assert version.returncode == 0 and version.stdout.startswith("raytracer ")


@pytest.mark.parametrize("flag", ["--sequential", "--simd"])
def test_accel_is_recorded_with_the_structure_it_built(raytracer, repo_root, tmp_path, flag):
    for accel in ("none", "bvh"):
        csv_path = tmp_path / f"{accel}.csv"
        done = run(raytracer, flag, repo_root / "scenes/random100.json", *SMALL, "--accel", accel, "--csv", csv_path)
        assert done.returncode == 0, done.stderr
        with csv_path.open(newline="") as f:
            assert {r["accel"] for r in csv.DictReader(f)} == {accel}
        meta = json.loads((tmp_path / f"{accel}.meta.json").read_text())
        assert meta["config"]["accel"] == accel
        structure = meta["accel_structure"]
        if accel == "none":
            assert structure is None
        else:
            # A binary tree that split the 100 spheres: an odd node count above 1.
            assert structure["kind"] == "bvh" and structure["nodes"] > 1 and structure["nodes"] % 2 == 1
            assert structure["build_ms"] > 0 and structure["depth"] >= 1
        assert meta["scene"]["load_ms"] > 0 and meta["prepare_ms"] > 0
    assert run(raytracer, flag, "--accel", "kd-tree", *SMALL).returncode == 2


def test_a_slow_load_says_so_on_stderr_and_a_fast_one_does_not(raytracer, repo_root):
    """A stage that runs over a second gets a line when it has, and its time
    when it ends; a scene read from a pipe whose writer waits 1.5 s is one."""
    scene = repo_root / "scenes/random20.json"
    args = ["--width", "8", "--height", "8", "--warmup", "0", "--frames", "1"]
    slow = f"{raytracer} <(sleep 1.5; cat {scene}) {' '.join(args)}"
    done = subprocess.run(["bash", "-c", slow], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    lines = done.stderr.splitlines()
    assert lines[0].startswith("raytracer: loading /dev/fd/") and lines[0].endswith(" ...")
    assert re.fullmatch(r"raytracer: loading /dev/fd/\d+: done in \d+\.\d s", lines[1]), lines
    quiet = subprocess.run(["bash", "-c", slow + " --quiet"], capture_output=True, text=True)
    assert quiet.returncode == 0 and quiet.stderr == ""
    fast = run(raytracer, scene, *args)
    assert fast.returncode == 0 and "raytracer: loading" not in fast.stderr


# The traversal axis and the counters belong to the SIMD kernel (schema:
# axes; the counters to the GPU renderer too); a combination that would
# record a setting the run ignored is refused before anything is rendered
# or written.
@pytest.mark.parametrize(
    "args, message",
    [
        (
            ["--sequential", "--accel", "bvh", "--traversal", "single"],
            "--traversal: renderer sequential does not take --traversal; --traversal applies to --simd and --simd-only",
        ),
        (
            ["--simd", "--accel", "none", "--traversal", "single"],
            "--traversal: --traversal single needs --accel bvh or auto (accel is none)",
        ),
        (["--simd-only", "--traversal", "hybrid"], "--traversal hybrid needs --accel bvh"),
        (
            ["--simd", "--accel", "bvh", "--traversal", "hybrid", "--hybrid-threshold", "0"],
            "--hybrid-threshold: expected a positive integer, got '0'",
        ),
        (
            ["--simd", "--accel", "bvh", "--hybrid-threshold", "4"],
            "--hybrid-threshold 4 needs --traversal hybrid (traversal is packet)",
        ),
        (
            ["--sequential", "--counters"],
            "--counters: renderer sequential does not take --counters; --counters applies to --simd, --simd-only "
            "and --gpu",
        ),
        (["--tbb-only", "--counters"], "renderer tbb_only does not"),
        (["--simd", "--accel", "bvh", "--traversal", "zigzag"], "--traversal: zigzag not in {packet,single,hybrid}"),
    ],
)
def test_bad_traversal_or_counters_exit_2_naming_the_option(raytracer, repo_root, tmp_path, args, message):
    done = run(raytracer, *args, repo_root / "scenes/random20.json", *SMALL, "--csv", tmp_path / "run.csv")
    assert done.returncode == 2, done.stderr
    assert done.stderr.splitlines()[-1].startswith("raytracer: "), "the reason is the last line"
    assert message in done.stderr
    assert list(tmp_path.iterdir()) == []


# The GPU renderer's axes (the CSV columns and metadata keys; schema:
# gpu_bvhs, gpu_schedules, gpu_paths): --gpu-bvh is refused for any other
# renderer, its default value too, and without a BVH; the retired variants'
# flags (schema: retired_gpu_variants) with any value, naming where their
# measurements are; all before anything is rendered or written.
GPU_AXES = ["gpu_bvh", "gpu_schedule", "gpu_path"]
RETIRED = schema.schema()["retired_gpu_variants"]


@pytest.mark.parametrize(
    "args, message",
    [
        *[
            (
                [renderer, "--accel", "bvh", "--gpu-bvh", entry["name"]],
                f"--gpu-bvh: renderer {schema_name} does not take --gpu-bvh; --gpu-bvh applies to --gpu",
            )
            for renderer, schema_name in [("--sequential", "sequential"), ("--simd", "simd_tbb")]
            for entry in schema.schema()["gpu_bvhs"]
        ],
        *[
            (
                ["--gpu", retired["flag"], value],
                f"{retired['flag']}: {retired['flag']} was retired: the GPU renderer always runs "
                f"{schema.schema()[retired['values']][0]['name']} now, so leave the option out; the measurements "
                f"of the retired {retired['name']} are in {retired['record']}",
            )
            for retired in RETIRED
            for value in (retired["name"], schema.schema()[retired["values"]][0]["name"], "tiles")
        ],
        (
            ["--gpu", "--gpu-bvh", "wide"],
            "--gpu-bvh: --gpu-bvh wide needs --accel bvh or auto (accel is none)",
        ),
        (
            ["--gpu", "--accel", "none", "--gpu-bvh", "binary"],
            "--gpu-bvh binary needs --accel bvh or auto (accel is none)",
        ),
        (["--gpu", "--accel", "bvh", "--gpu-bvh", "quad"], "--gpu-bvh: quad not in {binary,wide,grid,auto}"),
        (["--gpu", "--traversal", "single", "--accel", "bvh"], "renderer gpu does not take --traversal"),
    ],
)
def test_bad_gpu_axes_exit_2_naming_the_option(raytracer, repo_root, tmp_path, args, message):
    done = run(raytracer, *args, repo_root / "scenes/random20.json", *SMALL, "--csv", tmp_path / "run.csv")
    assert done.returncode == 2, done.stderr
    assert done.stderr.splitlines()[-1].startswith("raytracer: "), "the reason is the last line"
    assert message in done.stderr
    assert list(tmp_path.iterdir()) == []


def read_rows(csv_path):
    with csv_path.open(newline="") as f:
        return list(csv.DictReader(f))


def test_traversal_and_counter_columns_are_empty_where_none_applies(raytracer, repo_root, tmp_path):
    csv_path = tmp_path / "run.csv"
    scene = repo_root / "scenes/random20.json"
    done = run(raytracer, "--sequential", "--accel", "bvh", scene, *SMALL, "--csv", csv_path)
    assert done.returncode == 0, done.stderr
    rows = read_rows(csv_path)
    counter_columns = schema.frame_csv_columns()[schema.frame_csv_columns().index("rays") :]
    columns = ["traversal", "hybrid_threshold", *GPU_AXES, *counter_columns]
    assert {r[c] for r in rows for c in columns} == {""}
    config = json.loads((tmp_path / "run.meta.json").read_text())
    assert config["config"]["traversal"] == "" and config["config"]["hybrid_threshold"] is None
    assert [config["config"][axis] for axis in GPU_AXES] == ["", "", ""]
    assert config["config"]["counters"] is False and config["lane_counters"] is None


def test_counters_is_recorded_in_the_config(raytracer, repo_root, tmp_path):
    csv_path = tmp_path / "run.csv"
    args = ["--simd-only", "--accel", "bvh", "--counters", repo_root / "scenes/random20.json", *SMALL]
    done = run(raytracer, *args, "--csv", csv_path)
    assert done.returncode == 0, done.stderr
    meta = json.loads((tmp_path / "run.meta.json").read_text())
    assert meta["config"]["counters"] is True
    assert schema.metadata_key_problems(meta) == []


def test_a_simd_bvh_run_records_the_packet_traversal(raytracer, repo_root, tmp_path):
    csv_path = tmp_path / "run.csv"
    done = run(raytracer, "--simd", "--accel", "bvh", repo_root / "scenes/random20.json", *SMALL, "--csv", csv_path)
    assert done.returncode == 0, done.stderr
    rows = read_rows(csv_path)
    assert {r["traversal"] for r in rows} == {"packet"}
    assert {r["hybrid_threshold"] for r in rows} == {""}
    assert {r["rays"] for r in rows} == {""}, "no counters without --counters"
    assert json.loads((tmp_path / "run.meta.json").read_text())["config"]["traversal"] == "packet"


COUNTED = ["--width", "40", "--height", "24", "--warmup", "1", "--frames", "2", "--quiet", "--counters"]


def counted_run(raytracer, scene, tmp_path, name, *flags):
    out = tmp_path / name
    out.mkdir()
    args = ["--simd", "--accel", "bvh", *flags, scene, *COUNTED, "--csv", out / "run.csv"]
    done = run(raytracer, *args, "--save-frame", f"2:{out / 'f.png'}")
    assert done.returncode == 0, done.stderr
    return read_rows(out / "run.csv"), json.loads((out / "run.meta.json").read_text()), (out / "f.png").read_bytes()


# The three traversals trace the same rays to the same spheres (same image,
# same rays per depth and shading), but walk the tree differently; each
# frame's counters are self-consistent and the metadata sums the measured ones.
def test_counters_of_the_three_traversals(raytracer, repo_root, tmp_path):
    scene = repo_root / "scenes/random1000.json"
    runs = {
        name: counted_run(raytracer, scene, tmp_path, name, "--traversal", name)
        for name in ("packet", "single", "hybrid")
    }
    images = {name: image for name, (_, _, image) in runs.items()}
    assert images["single"] == images["packet"] and images["hybrid"] == images["packet"]
    for name, (rows, meta, _) in runs.items():
        for r in rows:
            per_depth = [int(n) for n in r["rays_per_depth"].split("/")]
            assert per_depth[0] == 40 * 24, "every pixel traces a primary ray"
            assert sum(per_depth) == int(r["rays"])
            assert per_depth == sorted(per_depth, reverse=True), "a bounce traces no more rays than the one before"
            for kind in ("node", "sphere", "shade"):
                assert 0 < int(r[f"{kind}_lanes_active"]) <= int(r[f"{kind}_lane_slots"]), (name, kind)
        measured = [r for r in rows if r["warmup"] == "0"]
        totals = meta["lane_counters"]
        assert totals["rays"] == sum(int(r["rays"]) for r in measured)
        assert totals["node_visits"] == sum(int(r["node_visits"]) for r in measured)
        assert meta["config"]["counters"] is True and meta["config"]["traversal"] == name
    packet, single, hybrid = (runs[n][0] for n in ("packet", "single", "hybrid"))
    for a, b in ((packet, single), (packet, hybrid)):
        for ra, rb in zip(a, b, strict=True):
            for column in ("rays_per_depth", "shade_lane_slots", "shade_lanes_active"):
                assert ra[column] == rb[column], column
    lanes = int(packet[0]["lanes"])
    assert {r["hybrid_threshold"] for r in hybrid} == {str(lanes - max(1, lanes // 8))}, "the default, made a number"
    # One ray against a wide node's children fills more of the vector than a fanned-out packet.
    occupancy = {
        n: int(rs[0]["node_lanes_active"]) / int(rs[0]["node_lane_slots"])
        for n, rs in (("packet", packet), ("single", single))
    }
    assert occupancy["single"] > occupancy["packet"]


# --csv to a special file (here a FIFO, as /dev/null is a device) streams the
# CSV into it: the file stays what it was (renaming over /dev/null as root
# once replaced the device with a file) and no sidecar lands beside it.
def test_csv_into_a_fifo_is_streamed_not_replaced(raytracer, repo_root, tmp_path):
    fifo = tmp_path / "frames.csv"
    os.mkfifo(fifo)
    reader = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)  # lets the raytracer open it without blocking
    try:
        done = run(raytracer, "--sequential", repo_root / "scenes/random20.json", *SMALL, "--csv", fifo)
        text = os.read(reader, 1 << 16).decode()
    finally:
        os.close(reader)
    assert done.returncode == 0, done.stderr
    assert stat.S_ISFIFO(fifo.stat().st_mode), "the FIFO was replaced by a file"
    assert text.splitlines()[0].startswith("run_id,"), text[:80]
    assert len(text.splitlines()) == 1 + 5, "header and the 2 + 3 frames"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["frames.csv"], "no sidecar, no temporary"


def gpu_run(raytracer, scene, tmp_path, *flags):
    csv_path = tmp_path / "run.csv"
    done = run(raytracer, "--gpu", *flags, scene, *SMALL, "--present", "none", "--csv", csv_path)
    assert done.returncode == 0, done.stderr
    return read_rows(csv_path), json.loads((tmp_path / "run.meta.json").read_text())


# The options are accepted for --gpu with either accel (--gpu-bvh with bvh
# only), and the run's config is complete; what the renderer did is below.
@pytest.mark.parametrize(
    "flags",
    [
        ["--accel", "bvh", "--gpu-bvh", "grid"],
        ["--accel", "bvh", "--gpu-bvh", "wide", "--counters"],
        ["--counters"],
    ],
)
def test_gpu_axes_and_counters_are_accepted_for_the_gpu_renderer(raytracer, repo_root, tmp_path, flags):
    rows, meta = gpu_run(raytracer, repo_root / "scenes/random20.json", tmp_path, *flags)
    assert {r["renderer"] for r in rows} == {"gpu"}
    assert meta["config"]["counters"] is ("--counters" in flags)
    assert {r["traversal"] for r in rows} == {""}, "the SIMD kernel's axis"
    assert schema.metadata_key_problems(meta) == []


# RendererInfo's gpuBvh, gpuSchedule and gpuPath are the GPU renderer's to
# fill (render/renderer.h): schedule and path always (their one remaining
# values since the others were retired), the BVH with accel bvh only.
@pytest.mark.parametrize(
    "flags, expected",
    [
        ([], ["", "pixel", "megakernel"]),
        (["--accel", "bvh"], ["binary", "pixel", "megakernel"]),
        (["--accel", "bvh", "--gpu-bvh", "wide"], ["wide", "pixel", "megakernel"]),
    ],
)
def test_a_gpu_run_records_its_axes(raytracer, repo_root, tmp_path, flags, expected):
    rows, meta = gpu_run(raytracer, repo_root / "scenes/random20.json", tmp_path, *flags)
    assert [{r[axis] for r in rows} for axis in GPU_AXES] == [{value} for value in expected]
    assert [meta["config"][axis] for axis in GPU_AXES] == expected


# A GPU run with --counters fills the counter columns and lane_counters as
# a SIMD run does (the columns' GPU meaning: schema frame_csv). Strict: once
# GPURenderer::lastCounters() reports, this passes and the marker must go.
@pytest.mark.parametrize("flags", [[], ["--accel", "bvh", "--gpu-bvh", "wide"]])
def test_a_gpu_run_with_counters_fills_the_counter_columns(raytracer, repo_root, tmp_path, flags):
    rows, meta = gpu_run(raytracer, repo_root / "scenes/random20.json", tmp_path, "--counters", *flags)
    for r in rows:
        assert r["rays_per_depth"] != "", f"frame {r['frame']}: no counters"
        per_depth = [int(n) for n in r["rays_per_depth"].split("/")]
        assert per_depth[0] == 24 * 16, "every pixel traces a primary ray"
        assert int(r["rays"]) == sum(per_depth)
        assert int(r["sphere_tests"]) > 0
        assert int(r["shade_lanes_active"]) <= int(r["shade_lane_slots"])
        if "bvh" in flags:
            assert 0 < int(r["node_lanes_active"]) <= int(r["node_lane_slots"])
    measured = [r for r in rows if r["warmup"] == "0"]
    totals = meta["lane_counters"]
    assert totals is not None
    assert totals["rays"] == sum(int(r["rays"]) for r in measured)
    assert totals["sphere_tests"] == sum(int(r["sphere_tests"]) for r in measured)


# --precision and --agreement (docs/render-model.md sections 8 and 10) =======================
EXIT_BAD_INPUT = 2


@pytest.mark.parametrize("renderer", ["--sequential", "--tbb-only", "--embree", "--gpu-rt"])
def test_half_precision_is_refused_by_the_renderers_outside_the_experiment(raytracer, repo_root, renderer):
    done = run(raytracer, renderer, "--precision", "f16", repo_root / "scenes/random20.json", *SMALL)
    assert done.returncode == EXIT_BAD_INPUT, done.stderr
    assert "--precision f16 applies to --simd, --simd-only and --gpu" in done.stderr


# The CPU features (/proc/cpuinfo flags) each Highway target with f16 kernels
# needs: x86's avx512_fp16, Arm's FP16 arithmetic (asimdhp) and what the
# target adds to it.
F16_TARGET_CPU_FLAGS = {
    "AVX3_SPR": {"avx512_fp16"},
    "NEON": {"asimdhp"},
    "NEON_WITHOUT_AES": {"asimdhp"},
    "NEON_BF16": {"asimdhp", "bf16"},
    "SVE": {"sve"},
    "SVE2": {"sve2"},
}


def cpu_flags() -> set[str]:
    flags = set()
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith(("flags", "Features")):
            flags |= set(line.split(":", 1)[1].split())
    return flags


def build_simd_targets(raytracer, repo_root, tmp_path) -> dict[str, bool]:
    """The Highway targets the binary under test was compiled for, each with
    whether its kernels compute in f16, from its metadata (build.simd_targets):
    what the build holds, not which target dispatch picks on this CPU."""
    done = run(raytracer, "--simd-only", repo_root / "scenes/random20.json", *SMALL, "--csv", tmp_path / "probe.csv")
    assert done.returncode == 0, done.stderr
    targets = json.loads((tmp_path / "probe.meta.json").read_text())["build"]["simd_targets"]
    assert targets, "a build compiles the SIMD kernels for one target at least"
    return {t["name"]: t["f16"] for t in targets}


def cpu_computes_in_f16(built: dict[str, bool], flags: set[str]) -> bool:
    """Whether the SIMD renderers must run --precision f16 here: the build has
    a target with f16 kernels and this CPU has what that target needs
    (docs/render-model.md section 10)."""
    unknown = [name for name, f16 in built.items() if f16 and name not in F16_TARGET_CPU_FLAGS]
    assert not unknown, f"targets with f16 kernels whose CPU flags this test does not know: {unknown}"
    return any(f16 and F16_TARGET_CPU_FLAGS[name] <= flags for name, f16 in built.items())


@pytest.mark.parametrize("renderer", ["--simd", "--simd-only"])
def test_the_simd_renderers_run_half_precision_exactly_where_the_cpu_computes_in_f16(
    raytracer, repo_root, renderer, tmp_path
):
    csv_path = tmp_path / "run.csv"
    done = run(raytracer, renderer, "--precision", "f16", repo_root / "scenes/random20.json", *SMALL, "--csv", csv_path)
    built = build_simd_targets(raytracer, repo_root, tmp_path)
    if cpu_computes_in_f16(built, cpu_flags()):
        assert done.returncode == 0, done.stderr
        with csv_path.open(newline="") as f:
            rows = list(csv.DictReader(f))
        assert {r["precision"] for r in rows} == {"f16"}
        assert json.loads((tmp_path / "run.meta.json").read_text())["config"]["precision"] == "f16"
        return
    assert done.returncode == EXIT_BAD_INPUT, done.stderr
    assert re.search(r"Highway target [A-Z0-9_]+ has no native f16 arithmetic \(Highway 1\.[0-9]+", done.stderr)
    assert "AVX3_SPR" in done.stderr and "NEON" in done.stderr
    assert not csv_path.exists(), "nothing rendered, nothing written"


def test_the_half_precision_refusal_names_the_preset_where_the_build_left_the_cpus_f16_target_out(
    raytracer, repo_root, tmp_path
):
    """A debug build (RT_SIMD_FEWER_TARGETS) on a CPU with AVX512-FP16 and a
    Highway that computes in f16 there: the refusal says the build, not the
    CPU, lacks the target, and names the preset that has it."""
    built = build_simd_targets(raytracer, repo_root, tmp_path)
    meta = json.loads((tmp_path / "probe.meta.json").read_text())
    highway = tuple(int(p) for p in meta["libraries"]["hwy"].split(".")[:2])
    if "avx512_fp16" not in cpu_flags() or highway < (1, 2) or "AVX3_SPR" in built:
        pytest.skip("only where the CPU has AVX512-FP16, Highway is 1.2 or newer and the build left AVX3_SPR out")
    done = run(raytracer, "--simd-only", "--precision", "f16", repo_root / "scenes/random20.json", *SMALL)
    assert done.returncode == EXIT_BAD_INPUT, done.stderr
    assert "This CPU runs AVX3_SPR, which computes in f16, but this build left that target out" in done.stderr
    assert "the release preset has it" in done.stderr


def test_the_metadata_lists_the_simd_targets_the_build_compiled(raytracer, repo_root, tmp_path):
    built = build_simd_targets(raytracer, repo_root, tmp_path)
    meta = json.loads((tmp_path / "probe.meta.json").read_text())
    assert meta["config"]["simd_target"] in built, "dispatch picks a compiled target"
    assert all(isinstance(f16, bool) for f16 in built.values())
    if meta["build"]["build_type"] == "Debug" and "AVX3" in built:
        assert "AVX3_SPR" not in built and "SSSE3" not in built, "the debug preset compiles one x86 target per width"


# What the f16 kernel does not cover is refused on every CPU, before the CPU is asked.
@pytest.mark.parametrize(
    ("extra", "message"),
    [(["--accel", "bvh"], "brute force only: use --accel none"), ([], "takes at most 2048 spheres")],
)
def test_the_simd_renderers_refuse_what_their_half_precision_kernel_lacks(
    raytracer, repo_root, tmp_path, extra, message
):
    scene = repo_root / "scenes/random20.json"
    if not extra:
        scene = tmp_path / "crowded.json"
        doc = json.loads((repo_root / "scenes/random20.json").read_text())
        doc["spheres"] = doc["spheres"] * (2049 // len(doc["spheres"]) + 1)
        scene.write_text(json.dumps(doc))
    csv_path = tmp_path / "run.csv"
    done = run(raytracer, "--simd-only", "--precision", "f16", *extra, scene, *SMALL, "--csv", csv_path)
    assert done.returncode == EXIT_BAD_INPUT, done.stderr
    assert message in done.stderr
    assert not csv_path.exists()


def test_every_renderer_records_f32_and_no_agreement_by_default(raytracer, repo_root, tmp_path):
    csv_path = tmp_path / "run.csv"
    done = run(raytracer, "--simd-only", repo_root / "scenes/random20.json", *SMALL, "--csv", csv_path)
    assert done.returncode == 0, done.stderr
    with csv_path.open(newline="") as f:
        assert {r["precision"] for r in csv.DictReader(f)} == {"f32"}
    meta = json.loads((tmp_path / "run.meta.json").read_text())
    assert meta["config"]["precision"] == "f32" and meta["config"]["agreement"] is False
    assert meta["agreement"] is None


def test_agreement_compares_frame_zero_with_the_double_reference(raytracer, repo_root, tmp_path):
    csv_path = tmp_path / "run.csv"
    args = [repo_root / "scenes/random20.json", *SMALL, "--present", "none", "--agreement"]
    done = run(raytracer, "--sequential", *args, "--csv", csv_path)
    assert done.returncode == 0, done.stderr
    agreement = json.loads((tmp_path / "run.meta.json").read_text())["agreement"]
    assert agreement["reference"] == "double" and agreement["frame"] == 0 and agreement["tolerance"] == 2
    # The sequential renderer agrees under section 8 (test_gpu_cli.py checks that f16 does not).
    assert agreement["within_tolerance"] >= 0.995 and agreement["max_channel_difference"] <= 2


# A brute-force run over a large scene says at once what it costs and what is
# faster, before it starts; a structure, or a small scene, starts quietly.
@pytest.mark.parametrize(
    ("scene", "extra", "noticed"),
    [("random10000", [], True), ("random10000", ["--accel", "bvh"], False), ("random1000", [], False)],
)
def test_brute_force_over_a_large_scene_says_what_it_costs(raytracer, repo_root, scene, extra, noticed):
    tiny = ["--width", "4", "--height", "4", "--warmup", "0", "--frames", "1", "--present", "none"]
    done = run(raytracer, "--sequential", repo_root / f"scenes/{scene}.json", *extra, *tiny)
    assert done.returncode == 0, done.stderr
    said = "brute force (--accel none) tests every ray against all 10000 spheres: 1.60e+05 sphere tests a frame"
    assert (said in done.stderr) == noticed, done.stderr
    if noticed:
        assert "--accel bvh" in done.stderr.split(said, 1)[1].splitlines()[0]


# --accel auto: the CSV and the metadata record what ran, the tree where it
# pays (a 1000-sphere scene) and brute force where it does not (20 spheres).
# The GPU renderer with a walk named (without one it probes them all:
# tests/gpu/test_gpu_cli.py).
@pytest.mark.parametrize(
    ("renderer", "scene", "ran"),
    [
        ("--simd", "random1000", "bvh"),
        ("--simd", "random20", "none"),
        ("--sequential", "ground500", "bvh"),
        ("--gpu --gpu-bvh binary", "random1000", "bvh"),
        ("--gpu --gpu-bvh binary", "random20", "none"),
    ],
)
def test_accel_auto_records_the_structure_that_ran(raytracer, repo_root, tmp_path, renderer, scene, ran):
    csv_path = tmp_path / "run.csv"
    scene_path = repo_root / f"scenes/{scene}.json"
    done = run(raytracer, *renderer.split(), "--accel", "auto", scene_path, *SMALL, "--csv", csv_path)
    assert done.returncode == 0, done.stderr
    with csv_path.open(newline="") as f:
        assert {r["accel"] for r in csv.DictReader(f)} == {ran}
    meta = json.loads((tmp_path / "run.meta.json").read_text())
    assert meta["config"]["accel"] == ran
    assert (meta["accel_structure"] is not None) == (ran == "bvh")
    if ran == "bvh":
        assert meta["accel_structure"]["estimated_tests_per_ray"] < 0.5 * meta["scene"]["spheres"]
