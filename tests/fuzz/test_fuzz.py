"""The fuzz harness in the test suite, bounded in time so that it fits a test run:

- the libFuzzer target of the scene loader (tests/fuzz/CMakeLists.txt, built
  here with clang into build/fuzz-libfuzzer), run for RT_LIBFUZZER_SECONDS
  (default 30) from the committed corpus;
- the mutation driver (fuzz_cli.py) over the binary under test ($RT_BINARY:
  in CI the ASan + UBSan debug build) for RT_FUZZ_SECONDS (default 45), with
  a fixed seed (RT_FUZZ_SEED) so a failure reproduces;
- every regression input in tests/fuzz/regressions/.

Longer campaigns: run fuzz_cli.py and the fuzzer binary by hand (their
--help and tests/fuzz/CMakeLists.txt say how)."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import fuzz_cli  # noqa: E402  (a script beside this test, not a package)


def regression_cases() -> list[Path]:
    return sorted((HERE / "regressions").glob("*.json"))


@pytest.mark.parametrize("path", regression_cases(), ids=lambda p: p.stem)
def test_regression_input_now_passes(raytracer, repo_root, path):
    spec = json.loads(path.read_text())
    data = spec["scene"].encode() if spec["scene"] is not None else None
    if spec["scene_from"]:
        data = (repo_root / spec["scene_from"]).read_bytes()
    category = "cli" if spec["args"] else "regression"
    case = fuzz_cli.Case(
        category, data=data, special=spec["special"], args=spec["args"], scene_message=not spec["args"]
    )
    verdict = fuzz_cli.run_case(raytracer.resolve(), case, timeout=120)
    assert verdict.failure is None, f"{spec['found']}: {verdict.failure}: {verdict.detail}"
    assert verdict.exit_code == spec["exit"], verdict


def test_mutation_driver_finds_nothing(raytracer, tmp_path):
    seconds = float(os.environ.get("RT_FUZZ_SECONDS", "45"))
    seed = int(os.environ.get("RT_FUZZ_SEED", "14"))
    summary = fuzz_cli.campaign(
        raytracer.resolve(), cases=100_000, seconds=seconds, seed=seed, jobs=2, timeout=120, keep=tmp_path / "failures"
    )
    print(json.dumps(summary, indent=1, sort_keys=True))
    assert sum(row["cases"] for row in summary.values()) > 0
    failed = {name: row["failures"] for name, row in summary.items() if row["failures"]}
    assert not failed, f"{failed}; inputs kept in {tmp_path / 'failures'}"


def build_libfuzzer_target(repo_root: Path) -> Path:
    """Configures and builds the clang project; skips where there is no clang
    (the Nix check phase), fails where clang cannot build it (setup-debian
    installs clang and its libFuzzer runtime)."""
    clang = shutil.which("clang++")
    if clang is None:
        pytest.skip("no clang++: the libFuzzer target needs clang (scripts/setup-debian installs it)")
    build = repo_root / "build" / "fuzz-libfuzzer"
    for cmd in (
        ["cmake", "-S", str(HERE), "-B", str(build), "-G", "Ninja", f"-DCMAKE_CXX_COMPILER={clang}"],
        ["cmake", "--build", str(build)],
    ):
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
        assert done.returncode == 0, done.stdout[-4000:] + done.stderr[-4000:]
    return build / "scene_loader_fuzzer"


def test_libfuzzer_scene_loader(repo_root, tmp_path):
    fuzzer = build_libfuzzer_target(repo_root)
    seconds = int(os.environ.get("RT_LIBFUZZER_SECONDS", "30"))
    corpus = tmp_path / "corpus"  # new inputs go here; the committed corpus stays as it is
    corpus.mkdir()
    done = subprocess.run(
        [
            str(fuzzer),
            f"-max_total_time={seconds}",
            "-timeout=10",
            "-rss_limit_mb=2048",
            f"-dict={HERE / 'scene.dict'}",
            f"-artifact_prefix={tmp_path}/",
            "-print_final_stats=1",
            str(corpus),
            str(HERE / "corpus"),
        ],
        capture_output=True,
        text=True,
        timeout=seconds + 120,
    )
    stats = [line for line in done.stderr.splitlines() if line.startswith("stat::") or line.startswith("Done")]
    print("\n".join(stats))
    assert done.returncode == 0, done.stderr[-6000:]
    assert any(line.startswith("Done") for line in stats), done.stderr[-2000:]
