"""The binary's Vulkan side, end to end: --list-devices, the no-device exit
(code 3), --present, --device, and a --gpu run under the validation layer."""

import csv
import json
import os
import re
import subprocess

import pytest

SMALL = ["--width", "48", "--height", "32", "--warmup", "1", "--frames", "2", "--quiet"]
EXIT_BAD_INPUT = 2
EXIT_NO_DEVICE = 3

# A loader that finds no driver at all: the "no device" path on any machine.
NO_DRIVER = {"VK_DRIVER_FILES": "/nonexistent.json", "VK_ICD_FILENAMES": "/nonexistent.json"}

DEVICE_LINE = re.compile(
    r"^  \d+[* ]  .+  type=(discrete|integrated|virtual|cpu|other)  driver=.+  api=\d+\.\d+\.\d+", re.M
)


def run(raytracer, *args, env=None):
    return subprocess.run(
        [raytracer, *map(str, args)], capture_output=True, text=True, env={**os.environ, **(env or {})}
    )


def read_csv(path):
    with path.open(newline="") as f:
        return list(csv.DictReader(f))


def test_list_devices(raytracer):
    done = run(raytracer, "--list-devices")
    assert done.returncode == 0, done.stderr
    lines = DEVICE_LINE.findall(done.stdout)
    assert lines, done.stdout
    assert done.stdout.startswith("Vulkan devices (index, name, type, driver, API version")
    assert len(re.findall(r"^  \d+\*", done.stdout, re.M)) == 1, "exactly one default device is marked"


def test_list_devices_without_a_driver_exits_3(raytracer):
    done = run(raytracer, "--list-devices", env=NO_DRIVER)
    assert done.returncode == EXIT_NO_DEVICE, done.stderr
    assert "no Vulkan device" in done.stderr


def test_gpu_without_a_driver_exits_3_and_says_what_it_found(raytracer, repo_root, tmp_path):
    done = run(
        raytracer, "--gpu", repo_root / "scenes/default.json", *SMALL, "--csv", tmp_path / "run.csv", env=NO_DRIVER
    )
    assert done.returncode == EXIT_NO_DEVICE, done.stderr
    assert "no Vulkan device" in done.stderr
    assert "VK_DRIVER_FILES=/nonexistent.json" in done.stderr, "names the loader setting it saw"
    assert not (tmp_path / "run.csv").exists(), "nothing rendered, nothing written"


def test_cpu_renderer_without_a_driver_presents_nowhere(raytracer, repo_root, tmp_path):
    csv_path = tmp_path / "run.csv"
    done = run(
        raytracer,
        "--sequential",
        repo_root / "scenes/default.json",
        "--width",
        "48",
        "--height",
        "32",
        "--warmup",
        "1",
        "--frames",
        "2",
        "--csv",
        csv_path,
        env=NO_DRIVER,
    )
    assert done.returncode == 0, done.stderr
    assert "note: no Vulkan device" in done.stderr
    rows = read_csv(csv_path)
    assert {r["present"] for r in rows} == {"none"}
    assert {r["device"] for r in rows} == {""}
    meta = json.loads((tmp_path / "run.meta.json").read_text())
    assert meta["device"] is None
    assert meta["config"]["present"] == "none"
    assert meta["config"]["present_reason"].startswith("default: no Vulkan device")


def test_explicit_upload_without_a_driver_exits_3(raytracer, repo_root):
    done = run(
        raytracer, "--sequential", repo_root / "scenes/default.json", *SMALL, "--present", "upload", env=NO_DRIVER
    )
    assert done.returncode == EXIT_NO_DEVICE, done.stderr


def test_unknown_device_exits_3_and_lists_the_devices(raytracer, repo_root):
    done = run(raytracer, "--gpu", repo_root / "scenes/default.json", *SMALL, "--device", "no-such-gpu-anywhere")
    assert done.returncode == EXIT_NO_DEVICE, done.stderr
    assert "no-such-gpu-anywhere" in done.stderr
    assert DEVICE_LINE.search(done.stderr), done.stderr


def test_bad_present_mode_is_bad_input(raytracer):
    assert run(raytracer, "--present", "swapchain").returncode == EXIT_BAD_INPUT


@pytest.mark.parametrize("present", ["upload", "none"])
def test_validated_gpu_run_records_gpu_time_and_the_device(raytracer, repo_root, tmp_path, present):
    csv_path = tmp_path / "run.csv"
    frame = tmp_path / "frame2.png"
    done = run(
        raytracer,
        "--gpu",
        repo_root / "scenes/random20.json",
        *SMALL,
        "--vk-validation",
        "--present",
        present,
        "--csv",
        csv_path,
        "--save-frame",
        f"2:{frame}",
    )
    assert done.returncode == 0, done.stderr
    assert "vulkan error" not in done.stderr and "vulkan warning" not in done.stderr, done.stderr
    rows = read_csv(csv_path)
    assert len(rows) == 3
    assert {r["renderer"] for r in rows} == {"gpu"}
    assert {r["present"] for r in rows} == {present}
    assert all(float(r["gpu_ms"]) > 0 for r in rows), "timestamps around every dispatch"
    assert all(float(r["gpu_ms"]) <= float(r["render_ms"]) * 1.05 + 0.05 for r in rows)
    meta = json.loads((tmp_path / "run.meta.json").read_text())
    device = meta["device"]
    assert device["name"] == rows[0]["device"] != ""
    assert device["validation"] is True
    for key in ("type", "driver_name", "driver_version", "api_version", "timestamp_period_ns"):
        assert device[key] not in ("", None), key
    assert frame.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_gpu_bvh_run_records_its_structure(raytracer, repo_root, tmp_path):
    csv_path = tmp_path / "run.csv"
    done = run(
        raytracer,
        "--gpu",
        repo_root / "scenes/random20.json",
        *SMALL,
        "--vk-validation",
        "--accel",
        "bvh",
        "--csv",
        csv_path,
    )
    assert done.returncode == 0, done.stderr
    assert {r["accel"] for r in read_csv(csv_path)} == {"bvh"}
    structure = json.loads((tmp_path / "run.meta.json").read_text())["accel_structure"]
    assert structure["kind"] == "bvh" and structure["nodes"] > 1


# --accel auto on the GPU renderer: the walk is chosen by a probe (--gpu-bvh
# auto, its default there), which runs at half the size of an image of more
# than 2^19 pixels; the CSV and metadata name what ran, and the image is
# brute force's.
def test_gpu_accel_auto_probes_the_walks_and_records_the_one_that_ran(raytracer, repo_root, tmp_path):
    size = ["--width", "1024", "--height", "600", "--warmup", "0", "--frames", "1"]
    scene = repo_root / "scenes/random20.json"
    auto_csv, auto_frame, brute_frame = tmp_path / "auto.csv", tmp_path / "auto.png", tmp_path / "brute.png"
    done = run(
        raytracer, "--gpu", scene, *size, "--accel", "auto", "--csv", auto_csv, "--save-frame", f"0:{auto_frame}"
    )
    assert done.returncode == 0, done.stderr
    assert "--gpu-bvh auto: probe frames of 512x300 took (gpu_ms) binary " in done.stderr, done.stderr
    probe = json.loads((tmp_path / "auto.meta.json").read_text())["gpu_walk_probe"]
    assert (probe["width"], probe["height"]) == (512, 300)
    assert list(probe["gpu_ms"]) == sorted(["binary", "wide", "grid", "none"])
    fastest = min(probe["gpu_ms"], key=probe["gpu_ms"].get)
    [row] = read_csv(auto_csv)
    assert (row["accel"], row["gpu_bvh"]) == (("none", "") if fastest == "none" else ("bvh", fastest))
    done = run(raytracer, "--gpu", scene, *size, "--quiet", "--save-frame", f"0:{brute_frame}")
    assert done.returncode == 0, done.stderr
    assert auto_frame.read_bytes() == brute_frame.read_bytes()


# Lavapipe's loop limit (render model section 8): a walk whose loops pass it
# (20,000 coincident spheres, no box to cull) fails the run with exit 2,
# naming the limit, and writes nothing, where lavapipe has that limit (Mesa
# 22.3); where it has not, the image agrees with the double reference.
def test_a_walk_past_lavapipes_loop_limit_fails_the_run_or_draws_right(raytracer, repo_root, tmp_path):
    scene = json.loads((repo_root / "scenes/default.json").read_text())
    scene["spheres"] = [
        {"position": [0.0, 0.0, 0.0], "radius": 1.0, "color": [1.0 - (i % 7) / 7, (i % 7) / 7, 0.5]}
        for i in range(20_000)
    ]
    pile = tmp_path / "pile.json"
    pile.write_text(json.dumps(scene))
    default = [line for line in run(raytracer, "--list-devices").stdout.splitlines() if re.match(r"^  \d+\*", line)]
    if not default or "driver=llvmpipe" not in default[0]:
        pytest.skip(f"lavapipe's limit; the default device is {default}")
    csv_path = tmp_path / "run.csv"
    done = run(raytracer, "--gpu", "--accel", "bvh", pile, *SMALL, "--agreement", "--csv", csv_path)
    if done.returncode == 0:
        agreement = json.loads((tmp_path / "run.meta.json").read_text())["agreement"]
        assert agreement["within_tolerance"] == 1.0, agreement
        return
    assert done.returncode == EXIT_BAD_INPUT, done.stderr
    assert "lavapipe ends a shader invocation's loops after 65535 iterations" in done.stderr, done.stderr
    assert "--gpu-bvh binary" in done.stderr
    assert not csv_path.exists() and not (tmp_path / "run.meta.json").exists()


def test_cpu_renderer_uploads_by_default_when_a_device_opens(raytracer, repo_root, tmp_path):
    csv_path = tmp_path / "run.csv"
    done = run(
        raytracer, "--sequential", repo_root / "scenes/default.json", *SMALL, "--vk-validation", "--csv", csv_path
    )
    assert done.returncode == 0, done.stderr
    rows = read_csv(csv_path)
    assert {r["present"] for r in rows} == {"upload"}
    assert all(r["gpu_ms"] == "" for r in rows)
    assert json.loads((tmp_path / "run.meta.json").read_text())["config"]["present_reason"].startswith("default")


# The ray-tracing pipeline renderer (gpu_rt) ===================================================
# Whether the default device offers an extension, asked of vulkaninfo (not of the binary under test).
def offers(extension):
    done = subprocess.run(["vulkaninfo"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    devices = re.split(r"^GPU\d+:$", done.stdout, flags=re.M)[1:]
    assert devices, "vulkaninfo lists no device"
    return re.search(rf"^\s*{re.escape(extension)}\s*:", devices[0], re.M) is not None


def test_gpu_rt_runs_validated_or_is_refused_where_the_device_lacks_the_pipeline(raytracer, repo_root, tmp_path):
    csv_path = tmp_path / "run.csv"
    done = run(raytracer, "--gpu-rt", repo_root / "scenes/random20.json", *SMALL, "--vk-validation", "--csv", csv_path)
    if not offers("VK_KHR_ray_tracing_pipeline"):
        assert done.returncode == EXIT_NO_DEVICE, done.stderr
        assert "VK_KHR_ray_tracing_pipeline" in done.stderr and "ray-tracing pipeline renderer" in done.stderr
        assert not csv_path.exists(), "nothing rendered, nothing written"
        return
    assert done.returncode == 0, done.stderr
    rows = read_csv(csv_path)
    assert {r["renderer"] for r in rows} == {"gpu_rt"}
    assert {r["accel"] for r in rows} == {"bvh"}, "the driver's structure is recorded as its own BVH"
    assert {r["gpu_rt_reorder"] for r in rows} == {"none"}
    assert {(r["gpu_bvh"], r["gpu_schedule"], r["gpu_path"]) for r in rows} == {("", "", "")}
    assert all(float(r["gpu_ms"]) > 0 for r in rows), "timestamps around every trace"
    meta = json.loads((tmp_path / "run.meta.json").read_text())
    structure = meta["accel_structure"]
    assert structure["device_bytes"] > 0 and structure["nodes"] is None and structure["depth"] is None
    assert meta["config"]["gpu_rt_reorder"] == "none"


def test_gpu_rt_hit_reorder_needs_nvidias_extension(raytracer, repo_root):
    if not offers("VK_KHR_ray_tracing_pipeline"):
        pytest.skip("no ray-tracing pipeline on this device (the test above checks the refusal)")
    done = run(raytracer, "--gpu-rt", "--gpu-rt-reorder", "hit", repo_root / "scenes/random20.json", *SMALL)
    if offers("VK_NV_ray_tracing_invocation_reorder"):
        assert done.returncode == 0, done.stderr
    else:
        assert done.returncode == EXIT_NO_DEVICE, done.stderr
        assert "VK_NV_ray_tracing_invocation_reorder" in done.stderr


@pytest.mark.parametrize(
    "args",
    [["--gpu-rt", "--accel", "none"], ["--gpu-rt", "--gpu-bvh", "wide"], ["--gpu", "--gpu-rt-reorder", "hit"]],
)
def test_gpu_rt_options_are_refused_where_they_do_not_apply(raytracer, repo_root, args):
    done = run(raytracer, *args, repo_root / "scenes/random20.json", *SMALL)
    assert done.returncode == EXIT_BAD_INPUT, done.stderr
    assert args[1] in done.stderr, "the message names the option"


# Half precision (--precision f16, docs/render-model.md section 10) ===========================
def offers_shader_float16():
    """Whether the default device offers shaderFloat16, asked of vulkaninfo."""
    done = subprocess.run(["vulkaninfo"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    device = re.split(r"^GPU\d+:$", done.stdout, flags=re.M)[1]
    found = re.search(r"^\s*shaderFloat16\s*=\s*(true|false)", device, re.M)
    assert found, "vulkaninfo names shaderFloat16 for the device"
    return found.group(1) == "true"


def test_gpu_half_precision_runs_validated_and_records_its_agreement(raytracer, repo_root, tmp_path):
    csv_path = tmp_path / "run.csv"
    args = ["--gpu", repo_root / "scenes/random20.json", *SMALL, "--vk-validation", "--agreement"]
    done = run(raytracer, *args, "--precision", "f16", "--csv", csv_path)
    if not offers_shader_float16():
        assert done.returncode == EXIT_BAD_INPUT, done.stderr
        assert "shaderFloat16" in done.stderr and "--precision f16" in done.stderr
        assert not csv_path.exists(), "nothing rendered, nothing written"
        return
    assert done.returncode == 0, done.stderr
    assert {r["precision"] for r in read_csv(csv_path)} == {"f16"}
    meta = json.loads((tmp_path / "run.meta.json").read_text())
    assert meta["config"]["precision"] == "f16" and meta["config"]["agreement"] is True
    half = meta["agreement"]
    assert half["reference"] == "double" and half["frame"] == 0 and half["tolerance"] == 2

    full_csv = tmp_path / "full.csv"
    done = run(raytracer, *args, "--csv", full_csv)
    assert done.returncode == 0, done.stderr
    assert {r["precision"] for r in read_csv(full_csv)} == {"f32"}
    full = json.loads((tmp_path / "full.meta.json").read_text())["agreement"]
    # The f32 frame agrees under section 8; the f16 one falls short of it.
    assert full["within_tolerance"] >= 0.995 and full["psnr_db"] >= 40
    assert half["within_tolerance"] < full["within_tolerance"] and half["psnr_db"] < 40
    assert half["max_channel_difference"] > full["max_channel_difference"]
