"""Loading run directories: the tidy frame, and clear errors naming the file
for truncated, corrupted or inconsistent input."""

import json
import shutil
from pathlib import Path

import pytest

from rtbench import load, names

FIXTURE = Path(__file__).parent / "fixtures" / "thesis-run"
ONE = "frames/random100-simd_tbb-optimized-r0"


@pytest.fixture
def run_copy(tmp_path):
    dst = tmp_path / "run"
    shutil.copytree(FIXTURE, dst)
    return dst


def test_fixture_loads_into_a_tidy_frame():
    frames = load.load_runs([FIXTURE])
    assert len(frames) == 60 * 4  # 60 runs x (1 warm-up + 3 measured)
    assert set(names.CSV_COLUMNS) <= set(frames.columns)
    assert set(frames[names.STAGE]) == set(names.STAGES)
    assert set(frames[names.DEVICE]) == {"Apple M1"}  # every renderer presented on the fixture's device
    assert set(frames[names.REPETITION]) == {0, 1}
    assert frames[names.WARMUP].sum() == 60


def test_stage_is_derived_from_algorithm_and_early_exits():
    assert names.stage_of("two-pass", "none") == "original"
    assert names.stage_of("single-pass", "bounce") == "single-pass"
    assert names.stage_of("single-pass", "discriminant+sphere+bounce") == "optimized"
    assert names.stage_of("two-pass", "bounce") == "two-pass[bounce]"


def test_truncated_csv_names_the_file_and_line(run_copy):
    path = run_copy / f"{ONE}.csv"
    text = path.read_text()
    path.write_text(text[: len(text) - 20])  # cut inside the last row
    with pytest.raises(load.RunDataError) as e:
        load.load_runs([run_copy])
    assert str(path) in str(e.value) and "line 5" in str(e.value) and "truncated" in str(e.value)


def test_csv_cut_at_a_row_boundary_disagrees_with_its_metadata(run_copy):
    path = run_copy / f"{ONE}.csv"
    lines = path.read_text().splitlines(keepends=True)
    path.write_text("".join(lines[:-1]))
    with pytest.raises(load.RunDataError, match=r"3 frames, but .* says 1 warm-up \+ 3 measured"):
        load.load_runs([run_copy])


@pytest.mark.parametrize(
    "edit, message",
    [
        (lambda t: t.replace("2917.53", "29x7.53"), "column render_ms: '29x7.53' is not a valid float"),
        (lambda t: t.replace("simd_tbb", "warp_drive", 1), "column renderer: unknown value 'warp_drive'"),
        (lambda t: t.replace("render_ms", "render_s"), "header does not match"),
        (lambda t: "", "empty file"),
        (lambda t: t.splitlines(keepends=True)[0], "header only"),
        (lambda t: t.replace(",2917.53,", ",inf,"), "not a valid float"),
        (lambda t: t.replace(",0.5,,\n", ",0.5,1.0,\n", 1), "gpu_ms is empty in 3 of 4 frames"),
    ],
)
def test_corrupted_csv_names_the_file(run_copy, edit, message):
    path = run_copy / f"{ONE}.csv"
    path.write_text(edit(path.read_text()))
    with pytest.raises(load.RunDataError) as e:
        load.load_runs([run_copy])
    assert str(e.value).startswith(str(path)) and message in str(e.value)


def test_broken_or_missing_metadata_names_the_sidecar(run_copy):
    meta = run_copy / f"{ONE}.meta.json"
    meta.write_text("{ not json")
    with pytest.raises(load.RunDataError, match=str(meta)):
        load.load_runs([run_copy])
    meta.unlink()
    with pytest.raises(load.RunDataError, match="metadata sidecar missing"):
        load.load_runs([run_copy])


def test_only_runs_the_manifest_calls_ok_are_loaded(run_copy):
    manifest = json.loads((run_copy / "manifest.json").read_text())
    for r in manifest["runs"]:
        if r["config"] == "random100-simd_tbb-optimized":
            r["status"] = "interrupted"
    (run_copy / "manifest.json").write_text(json.dumps(manifest))
    frames = load.load_runs([run_copy])
    assert len(frames) == 58 * 4


def test_directory_without_manifest_loads_every_csv(tmp_path):
    for name in ("a", "b"):
        src = FIXTURE / f"frames/default-sequential-original-r{0 if name == 'a' else 1}"
        shutil.copy(f"{src}.csv", tmp_path / f"{name}.csv")
        shutil.copy(f"{src}.meta.json", tmp_path / f"{name}.meta.json")
    frames = load.load_runs([tmp_path])
    assert sorted(set(frames[names.REPETITION])) == [0, 1]


def test_no_finished_runs_is_an_error(tmp_path):
    with pytest.raises(load.RunDataError, match="no finished runs"):
        load.load_runs([tmp_path])
    with pytest.raises(load.RunDataError, match="not a directory"):
        load.load_runs([tmp_path / "missing"])


def test_fixture_is_what_its_generator_writes(tmp_path, repo_root):
    """The committed fixture follows the schema of today: regenerate it with
    make_thesis_run.py after a schema change."""
    import os
    import subprocess
    import sys

    out = tmp_path / "regenerated"
    env = {**os.environ, "PYTHONPATH": str(repo_root / "scripts")}
    subprocess.run(
        [sys.executable, FIXTURE.parent / "make_thesis_run.py", "-o", out], check=True, capture_output=True, env=env
    )
    committed = sorted(p.relative_to(FIXTURE) for p in FIXTURE.rglob("*") if p.is_file())
    assert committed == sorted(p.relative_to(out) for p in out.rglob("*") if p.is_file())
    for rel in committed:
        assert (out / rel).read_bytes() == (FIXTURE / rel).read_bytes(), f"{rel} drifted: rerun make_thesis_run.py"


def test_the_device_is_the_csv_column(run_copy):
    """The CSV names the device each run used; the loader takes it from there,
    never from the metadata sidecar."""
    path = run_copy / f"{ONE}.csv"
    path.write_text(path.read_text().replace(",Apple M1,", ",llvmpipe (LLVM 15.0.6; 256 bits),"))
    frames = load.load_runs([run_copy])
    one = frames[frames[names.SOURCE] == f"run/{ONE}.csv"]
    assert set(one[names.DEVICE]) == {"llvmpipe (LLVM 15.0.6; 256 bits)"}
    assert set(frames[frames[names.SOURCE] != f"run/{ONE}.csv"][names.DEVICE]) == {"Apple M1"}
