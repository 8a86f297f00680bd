"""The frame CSV's GPU variant columns (gpu_bvh, gpu_schedule, gpu_path):
CSVs written before them load as the one variant the GPU renderer had then
(binary BVH where accel bvh, one invocation per pixel, one dispatch), the
CPU renderers with none; values that cannot be right stop the loader with an
error naming the file and the line; the runs of retired variants (schema:
retired_gpu_variants) are left out, with one line that says how many and
why; the GPU renderer's counters load."""

import csv
import io
import shutil
from pathlib import Path

import pytest
from synthetic_runs import SyntheticConfig, write_run_dir

from rtbench import load, names

FIXTURE = Path(__file__).parent / "fixtures" / "thesis-run"
GPU_RUN = "frames/random100-gpu-optimized-r0"
GPU_BVH = SyntheticConfig(renderer="gpu", threads=0, lanes=0, accel="bvh")
WIDE = SyntheticConfig(
    renderer="gpu", threads=0, lanes=0, accel="bvh", gpu_bvh="wide", gpu_schedule="pixel", gpu_path="megakernel"
)
# The retired variants as the reference runs recorded them.
PERSISTENT = SyntheticConfig(renderer="gpu", threads=0, lanes=0, gpu_schedule="persistent", gpu_path="megakernel")
WAVEFRONT = SyntheticConfig(
    renderer="gpu", threads=0, lanes=0, accel="bvh", gpu_bvh="wide", gpu_schedule="pixel", gpu_path="wavefront"
)
# The GPU columns: the axes, and the retired axes' columns the CSV keeps.
GPU_COLUMNS = [names.GPU_BVH, names.GPU_SCHEDULE, names.GPU_PATH, names.GPU_RT_REORDER]
SIMD = SyntheticConfig(accel="bvh", traversal="single")
TIMES = [[9.0, 5.0, 5.5, 6.0]]
# A GPU frame's counts (one warm-up frame, then three), per subgroup: slots >= active.
GPU_COUNTS = {
    "rays": [4000, 4100, 4200, 4300],
    "rays_per_depth": ["3072/928", "3072/1028", "3072/1128", "3072/1228"],
    "node_visits": [90_000, 91_000, 92_000, 93_000],
    "node_lane_slots": [160_000, 161_000, 162_000, 163_000],
    "node_lanes_active": [90_000, 91_000, 92_000, 93_000],
    "sphere_tests": [20_000, 21_000, 22_000, 23_000],
    "sphere_lane_slots": [40_000, 41_000, 42_000, 43_000],
    "sphere_lanes_active": [20_000, 21_000, 22_000, 23_000],
    "shade_lane_slots": [4096, 4096, 4096, 4096],
    "shade_lanes_active": [3000, 3100, 3200, 3300],
    "gpu_ms": [1.5, 1.0, 1.1, 1.2],
}


def test_the_fixture_was_written_before_the_gpu_columns():
    header = (FIXTURE / f"{GPU_RUN}.csv").read_text().splitlines()[0].split(",")
    assert not {"gpu_bvh", "gpu_schedule", "gpu_path"} & set(header)


def test_an_older_csv_of_the_gpu_renderer_ran_the_default_variant():
    frames = load.load_runs([FIXTURE])
    gpu = frames[names.RENDERER] == "gpu"
    assert gpu.any() and (~gpu).any()
    # Brute force: no BVH to walk, one invocation per pixel, one dispatch per frame (hand-written values).
    assert set(zip(*(frames.loc[gpu, axis] for axis in GPU_COLUMNS))) == {("", "pixel", "megakernel", "")}
    assert set(zip(*(frames.loc[~gpu, axis] for axis in GPU_COLUMNS))) == {("", "", "", "")}


def test_an_older_csv_of_the_gpu_renderer_on_the_bvh_walked_the_binary_bvh(tmp_path):
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    for suffix in (".csv", ".meta.json"):
        path = run / f"{GPU_RUN}{suffix}"
        path.write_text(path.read_text().replace(",none,800,", ",bvh,800,").replace('"none"', '"bvh"'))
    frames = load.load_runs([run])
    edited = frames[names.SOURCE] == f"run/{GPU_RUN}.csv"
    assert set(zip(*(frames.loc[edited, axis] for axis in GPU_COLUMNS))) == {("binary", "pixel", "megakernel", "")}


def test_the_columns_load_as_written_and_name_configurations_apart(tmp_path):
    write_run_dir(tmp_path, {GPU_BVH: TIMES, WIDE: TIMES, SIMD: TIMES})
    frames = load.load_runs([tmp_path])
    simd = frames[names.RENDERER] == "simd_tbb"
    assert set(zip(*(frames.loc[simd, axis] for axis in GPU_COLUMNS))) == {("", "", "", "")}
    # GPU_BVH left the columns empty, as a CSV before them: the loader fills in the default.
    variants = set(zip(*(frames.loc[frames[names.RENDERER] == "gpu", a] for a in GPU_COLUMNS)))
    assert variants == {("binary", "pixel", "megakernel", ""), ("wide", "pixel", "megakernel", "")}
    assert frames.groupby(names.CONFIG_KEYS, dropna=False).ngroups == 3


def test_runs_of_retired_variants_are_left_out_with_one_line(tmp_path):
    write_run_dir(tmp_path, {GPU_BVH: TIMES * 2, WIDE: TIMES, PERSISTENT: TIMES * 3, WAVEFRONT: TIMES, SIMD: TIMES})
    frames, note = load.load_kept_runs([tmp_path])
    assert set(frames[names.CONFIG_ID]) == {GPU_BVH.id, WIDE.id, SIMD.id}
    assert set(frames[names.GPU_SCHEDULE]) == {"pixel", ""} and set(frames[names.GPU_PATH]) == {"megakernel", ""}
    assert note.startswith("4 run(s) of 2 configuration(s) left out: they ran retired GPU variants ")
    assert "(gpu_schedule persistent, gpu_path wavefront)" in note
    assert note.endswith("are in docs/experiments/gpu-traversal.md")
    assert load.load_runs([tmp_path]).equals(frames)


def test_a_run_without_retired_variants_has_no_note(tmp_path):
    write_run_dir(tmp_path, {GPU_BVH: TIMES, WIDE: TIMES})
    assert load.load_kept_runs([tmp_path])[1] is None


def test_only_retired_runs_leave_nothing_to_report(tmp_path):
    write_run_dir(tmp_path, {PERSISTENT: TIMES})
    with pytest.raises(load.RunDataError, match="nothing left to report: 1 run"):
        load.load_kept_runs([tmp_path])


def test_gpu_counters_load_beside_gpu_ms(tmp_path):
    write_run_dir(tmp_path, {WIDE: TIMES}, counters={WIDE: GPU_COUNTS})
    frames = load.load_runs([tmp_path])
    for column, values in GPU_COUNTS.items():
        assert list(frames[column]) == values, column
    assert frames[names.RAYS].dtype == "Int64"


def _rewrite(path: Path, edit) -> None:
    rows = list(csv.DictReader(io.StringIO(path.read_text())))
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=list(rows[0]), lineterminator="\n")
    writer.writeheader()
    for row in rows:
        edit(row)
        writer.writerow(row)
    path.write_text(out.getvalue())


@pytest.mark.parametrize(
    "config, column, value, message",
    [
        (WIDE, "gpu_bvh", "quad", "column gpu_bvh: unknown value 'quad'"),
        (WIDE, "gpu_schedule", "lazy", "column gpu_schedule: unknown value 'lazy'"),
        (WIDE, "gpu_path", "Wavefront", "column gpu_path: unknown value 'Wavefront'"),
        (
            SIMD,
            "gpu_path",
            "wavefront",
            "line 2: column gpu_path: wavefront with renderer simd_tbb (applies to the gpu",
        ),
        (
            SIMD,
            "gpu_schedule",
            "pixel",
            "line 2: column gpu_schedule: pixel with renderer simd_tbb (applies to the gpu",
        ),
        (
            SyntheticConfig(renderer="gpu", threads=0, lanes=0),
            "gpu_bvh",
            "wide",
            "line 2: column gpu_bvh: wide with renderer gpu, accel none (applies to the gpu renderer with accel bvh",
        ),
    ],
)
def test_impossible_gpu_values_name_the_file(tmp_path, config, column, value, message):
    write_run_dir(tmp_path, {config: TIMES})
    (path,) = tmp_path.glob("frames/*.csv")

    def edit(row):
        row[column] = value

    _rewrite(path, edit)
    with pytest.raises(load.RunDataError) as e:
        load.load_runs([tmp_path])
    assert str(e.value).startswith(str(path)) and message in str(e.value)
