"""The aarch64 build (preset aarch64, cross-compiled) run under qemu-user on
x86-64: every renderer's image byte for byte the x86-64 build's, on a NEON
CPU without SVE (cortex-a72) and on qemu's `max` (SVE2, FP16, BF16), whose
SIMD renderers run SVE2 at 128, 256 and 512-bit vectors and report the lanes
that gives; the run metadata marks the run as emulated, and neither the
bench runner nor the report takes its timings as speed.

Needs the aarch64 preset's binary ($RT_AARCH64_BINARY, else
build/aarch64/raytracer) and qemu-aarch64; scripts/test builds it when
RT_TEST_PRESETS names aarch64, and these tests skip, saying so, elsewhere."""

from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
from pathlib import Path

import pytest

from rtbench import emulation, load, precision

# The emulated CPUs: NEON without SVE (a Raspberry Pi 4's core), and qemu's
# everything-on model (SVE2, FP16, BF16) at each of SVE's vector lengths
# that machines have: 128 bits (Neoverse N2, Graviton 4), 256 (Graviton 3,
# Neoverse V1), 512 (A64FX); qemu-user's default is 512.
SVE_CPUS = {bits: f"max,sve-default-vector-length={bits // 8}" for bits in (128, 256, 512)}
CPUS = ("cortex-a72", "max")
SIZE = ["--width", "160", "--height", "120"]
SMALL = ["--width", "64", "--height", "48"]
# One image per configuration: every CPU renderer of ours on both accels and
# the thesis' stages, the SIMD kernel's traversals and lane widths; the GPU
# renderer on arm64 lavapipe at a smaller size (lavapipe's JIT under qemu is
# slow). Embree computes its own way on each architecture: tested apart.
CONFIGS = {
    "sequential": ["--sequential"],
    "sequential_bvh": ["--sequential", "--accel", "bvh"],
    "tbb_only": ["--tbb-only"],
    "simd_only_original": ["--simd-only", "--stage", "original"],
    "simd_only_optimized": ["--simd-only", "--stage", "optimized"],
    "simd_only_lanes4": ["--simd-only", "--lanes", "4"],
    "simd_tbb": ["--simd"],
    "simd_tbb_bvh_packet": ["--simd", "--accel", "bvh", "--traversal", "packet"],
    "simd_tbb_bvh_single": ["--simd", "--accel", "bvh", "--traversal", "single"],
    "simd_tbb_bvh_hybrid": ["--simd", "--accel", "bvh", "--traversal", "hybrid"],
    "gpu": ["--gpu", *SMALL],
    "gpu_bvh": ["--gpu", "--accel", "bvh", *SMALL],
}


@pytest.fixture(scope="module")
def aarch64_raytracer(repo_root) -> Path:
    given = os.environ.get("RT_AARCH64_BINARY")
    binary = Path(given) if given else repo_root / "build/aarch64/raytracer"
    if not binary.is_file():
        pytest.skip(f"no aarch64 build at {binary}: build the aarch64 preset (RT_TEST_PRESETS='... aarch64')")
    if shutil.which("qemu-aarch64") is None:
        pytest.skip("no qemu-aarch64: scripts/setup-debian --cross aarch64 installs it")
    return binary


# lavapipe's manifest for arm64: Debian 12 names one per architecture, Debian
# 13 one for all (its library path relative, so the arm64 loader opens the
# arm64 library).
LAVAPIPE_ICDS = [Path("/usr/share/vulkan/icd.d/lvp_icd.aarch64.json"), Path("/usr/share/vulkan/icd.d/lvp_icd.json")]


def emulated_env(cpu: str) -> dict[str, str]:
    env = {**os.environ, "QEMU_CPU": cpu}
    # lavapipe only: the loader would otherwise try, and fail, every x86-64 driver first.
    icd = next((p for p in LAVAPIPE_ICDS if p.is_file()), None)
    if icd is not None:
        env["VK_ICD_FILENAMES"] = str(icd)
    return env


def render(command: list, scene: Path, out: Path, args: list[str], env=None) -> Path:
    png = out.with_suffix(".png")
    done = subprocess.run(
        [
            *map(str, command),
            str(scene),
            *(args if "--width" in args else [*SIZE, *args]),
            "--warmup",
            "0",
            "--frames",
            "1",
            "--present",
            "none",
            "-q",
            "--csv",
            str(out.with_suffix(".csv")),
            "--save-frame",
            f"0:{png}",
        ],
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr
    return png


@pytest.fixture(scope="module")
def x86_images(raytracer, repo_root, tmp_path_factory) -> dict[str, bytes]:
    out = tmp_path_factory.mktemp("x86")
    scene = repo_root / "scenes/random20.json"
    return {name: render([raytracer], scene, out / name, args).read_bytes() for name, args in CONFIGS.items()}


def emulated_image(aarch64_raytracer, repo_root, tmp_path, config: str, cpu: str) -> bytes:
    """The PNG of configuration `config` from the aarch64 build on emulated CPU `cpu`."""
    scene = repo_root / "scenes/random20.json"
    png = render(["qemu-aarch64", aarch64_raytracer], scene, tmp_path / config, CONFIGS[config], emulated_env(cpu))
    return png.read_bytes()


@pytest.mark.parametrize("cpu", CPUS)
@pytest.mark.parametrize("config", CONFIGS)
def test_every_renderer_draws_the_x86_image_byte_for_byte(
    aarch64_raytracer, repo_root, tmp_path, x86_images, cpu, config
):
    assert emulated_image(aarch64_raytracer, repo_root, tmp_path, config, cpu) == x86_images[config]


SIMD_CONFIGS = [name for name in CONFIGS if name.startswith("simd_")]


@pytest.mark.parametrize("bits", [128, 256])
@pytest.mark.parametrize("config", SIMD_CONFIGS)
def test_sve_at_each_vector_length_draws_the_x86_image_byte_for_byte(
    aarch64_raytracer, repo_root, tmp_path, x86_images, bits, config
):
    """512 bits is `max` above; the other configurations do not run SVE."""
    assert emulated_image(aarch64_raytracer, repo_root, tmp_path, config, SVE_CPUS[bits]) == x86_images[config]


@pytest.mark.parametrize("bits", sorted(SVE_CPUS))
def test_sve_runs_at_the_vector_length_and_reports_its_lanes(aarch64_raytracer, repo_root, tmp_path, bits):
    scene = repo_root / "scenes/default.json"
    native = bits // 32
    for lanes in ("native", "4", "8", "16"):
        out = tmp_path / f"lanes{lanes}"
        done = subprocess.run(
            [
                "qemu-aarch64",
                str(aarch64_raytracer),
                str(scene),
                *SMALL,
                *["--simd-only", "--lanes", lanes, "--warmup", "0", "--frames", "1", "--present", "none", "-q"],
                *["--csv", str(out.with_suffix(".csv"))],
            ],
            capture_output=True,
            text=True,
            env=emulated_env(SVE_CPUS[bits]),
            timeout=600,
        )
        if lanes != "native" and int(lanes) > native:
            assert done.returncode == 2, done.stderr
            assert f"--lanes {lanes}" in done.stderr
            continue
        assert done.returncode == 0, done.stderr
        config = json.loads(out.with_suffix(".meta.json").read_text())["config"]
        assert config["simd_target"] == "SVE2"
        assert config["lanes"] == (native if lanes == "native" else int(lanes))
        header, row = (line.split(",") for line in out.with_suffix(".csv").read_text().splitlines()[:2])
        assert row[header.index("lanes")] == str(config["lanes"])
        assert row[header.index("simd_target")] == "SVE2"


@pytest.mark.parametrize("cpu", CPUS)
def test_embree_agrees_with_the_double_reference_as_on_x86(aarch64_raytracer, repo_root, tmp_path, cpu):
    """Embree's own traversal arithmetic differs on NEON (sse2neon), so its
    image is held to section 8's rule against the double reference rather
    than to x86-64's bytes."""
    render(
        ["qemu-aarch64", aarch64_raytracer],
        repo_root / "scenes/random20.json",
        tmp_path / "embree",
        ["--embree", "--agreement"],
        emulated_env(cpu),
    )
    agreement = json.loads((tmp_path / "embree.meta.json").read_text())["agreement"]
    psnr_db = math.inf if agreement["psnr_db"] is None else agreement["psnr_db"]  # None: identical
    assert precision.agrees(agreement["within_tolerance"], psnr_db) == 1.0, agreement


@pytest.mark.parametrize("cpu", CPUS)
def test_the_metadata_marks_the_emulated_run_and_the_native_one_not(
    raytracer, aarch64_raytracer, repo_root, tmp_path, cpu
):
    scene = repo_root / "scenes/default.json"
    render(["qemu-aarch64", aarch64_raytracer], scene, tmp_path / "emulated", ["--simd-only"], emulated_env(cpu))
    render([raytracer], scene, tmp_path / "native", ["--simd-only"])
    emulated = json.loads((tmp_path / "emulated.meta.json").read_text())
    native = json.loads((tmp_path / "native.meta.json").read_text())
    assert emulated["host"]["emulation"] == {
        "emulator": "qemu-aarch64",
        "cpu": cpu,
        "host_architecture": emulation.host_architecture(),
    }
    assert emulated["host"]["kernel"].endswith("aarch64")  # qemu-user reports the guest's machine
    assert native["host"]["emulation"] is None


def test_the_report_refuses_an_emulated_run(aarch64_raytracer, repo_root, tmp_path):
    scene = repo_root / "scenes/default.json"
    render(["qemu-aarch64", aarch64_raytracer], scene, tmp_path / "emulated", ["--simd-only"], emulated_env("max"))
    csv, meta = tmp_path / "emulated.csv", tmp_path / "emulated.meta.json"
    with pytest.raises(load.RunDataError, match=r"emulated\.meta\.json: an emulated run \(qemu-aarch64 emulating max"):
        load.load_one(csv, meta, "simd_only", 0, "test")


def test_the_bench_runner_refuses_the_aarch64_binary_before_it_starts(aarch64_raytracer, repo_root, tmp_path):
    runs = tmp_path / "runs"
    done = subprocess.run(
        [
            str(repo_root / "scripts/bench"),
            "--binary",
            str(aarch64_raytracer),
            "--runs-dir",
            str(runs),
            "--profile",
            "quick",
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode != 0
    assert f"is an aarch64 binary and this machine is {emulation.host_architecture()}" in done.stderr
    assert not runs.exists() or not any(runs.iterdir())
