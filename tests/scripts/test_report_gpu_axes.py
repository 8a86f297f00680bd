"""The report of runs with the GPU renderer's variants: the variants named in
the accel column, the GPU section's table of gpu_ms medians and speedups over
the default variant (numbers checked against ones computed here), Mrays/s
from gpu_ms for the GPU renderer, its counters in the lane-occupancy section,
the thesis' tables on the default variant, the runs of retired variants left
out with a warning that says so; and no GPU section without variants."""

from __future__ import annotations

import csv
import statistics

import pytest
from synthetic_runs import SyntheticConfig, table_rows, write_run_dir

from rtbench import report_writer

GPU = {"renderer": "gpu", "threads": 0, "lanes": 0}
SEQUENTIAL = SyntheticConfig(renderer="sequential", threads=1, lanes=1)
KEPT = {"gpu_schedule": "pixel", "gpu_path": "megakernel"}
BRUTE = SyntheticConfig(**GPU, **KEPT)
BVH = SyntheticConfig(**GPU, **KEPT, accel="bvh", gpu_bvh="binary")
WIDE = SyntheticConfig(**GPU, **KEPT, accel="bvh", gpu_bvh="wide")
# Only a grid run, no default beside it at its stage: no speedup over the default.
LONE = SyntheticConfig(**GPU, **KEPT, stage="original", accel="bvh", gpu_bvh="grid")
# Retired variants (schema: retired_gpu_variants), as the reference runs have them: left out.
BRUTE_PERSISTENT = SyntheticConfig(**GPU, gpu_schedule="persistent", gpu_path="megakernel")
WIDE_WAVEFRONT = SyntheticConfig(**GPU, accel="bvh", gpu_bvh="wide", gpu_schedule="persistent", gpu_path="wavefront")
WARMUP = 1
# render_ms of one repetition (the first frame a warm-up frame) and gpu_ms of each frame.
TIMES = {
    SEQUENTIAL: [[90.0, 60.0, 61.0, 62.0]],
    BRUTE: [[9.0, 5.0, 5.5, 6.0]],
    BRUTE_PERSISTENT: [[9.0, 7.0, 7.5, 8.0], [9.0, 7.0, 7.5, 8.0]],
    BVH: [[3.0, 2.0, 2.2, 2.4]],
    WIDE: [[3.0, 1.5, 1.6, 1.7]],
    WIDE_WAVEFRONT: [[3.0, 1.4, 1.5, 1.6]],
    LONE: [[3.0, 1.8, 1.9, 2.0]],
}
GPU_MS = {
    BRUTE: [1.0, 0.5, 0.6, 0.7],
    BRUTE_PERSISTENT: [1.0, 0.7, 0.8, 0.9],
    BVH: [1.0, 0.8, 0.9, 1.0],
    WIDE: [1.0, 0.4, 0.45, 0.5],
    WIDE_WAVEFRONT: [1.0, 0.3, 0.35, 0.4],
    LONE: [1.0, 0.6, 0.7, 0.8],
}
# Counters of the GPU on the BVH, per subgroup: 32 slots per step of the busiest invocation.
RAYS = [5000, 6000, 6400, 6600]
COUNTS = {
    "rays": RAYS,
    "rays_per_depth": [f"4608/{r - 4608}" for r in RAYS],
    "node_visits": [100, 100, 100, 100],
    "node_lane_slots": [320, 320, 320, 320],
    "node_lanes_active": [100, 100, 100, 100],
    "sphere_tests": [10, 10, 10, 10],
    "sphere_lane_slots": [64, 64, 64, 64],
    "sphere_lanes_active": [10, 10, 10, 10],
    "shade_lane_slots": [32, 32, 32, 32],
    "shade_lanes_active": [16, 16, 16, 16],
}


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    base = tmp_path_factory.mktemp("gpu-axes")
    counters = {config: {"gpu_ms": ms} for config, ms in GPU_MS.items()}
    counters[BVH] = {**counters[BVH], **COUNTS}
    run = write_run_dir(base / "run", TIMES, warmup=WARMUP, counters=counters)
    out = base / "report"
    assert report_writer.main([str(run), "-o", str(out), "-q"]) == 0
    return out


def median_gpu_ms(config) -> float:
    return statistics.median(GPU_MS[config][WARMUP:])


def test_the_accel_column_names_the_variants_that_are_not_the_default(report):
    rows = table_rows((report / "tables/summary.md").read_text())
    gpu = sorted((r[0], r[3]) for r in rows if r[2] == "gpu")
    assert gpu == sorted(
        [("optimized", "none"), ("optimized", "bvh"), ("optimized", "bvh wide"), ("original", "bvh grid")]
    )
    with (report / "data/summary.csv").open() as f:
        data = list(csv.DictReader(f))
    assert {(r["renderer"], r["accel"], r["gpu_bvh"], r["gpu_schedule"], r["gpu_path"]) for r in data} == {
        ("sequential", "none", "", "", ""),
        ("gpu", "none", "", "pixel", "megakernel"),
        ("gpu", "bvh", "binary", "pixel", "megakernel"),
        ("gpu", "bvh", "wide", "pixel", "megakernel"),
        ("gpu", "bvh", "grid", "pixel", "megakernel"),
    }


def test_the_runs_of_retired_variants_are_left_out_with_a_warning(report):
    readme = (report / "README.md").read_text()
    warnings = readme.split("## Warnings\n", 1)[1].split("\n## ", 1)[0]
    (line,) = [w for w in warnings.splitlines() if "retired" in w]
    assert line.startswith("- 3 run(s) of 2 configuration(s) left out: they ran retired GPU variants ")
    assert "(gpu_schedule persistent, gpu_path wavefront)" in line and "docs/experiments/gpu-traversal.md" in line
    for name in ("persistent", "wavefront"):
        assert name not in readme.replace(line, ""), f"{name} shows beyond the warning"
        for table in (report / "tables").glob("*.md"):
            assert name not in table.read_text(), table.name


def test_the_gpu_section_gives_each_variants_gpu_ms_and_speedup_over_the_default(report):
    table = (report / "tables/gpu-variants.md").read_text()
    rows = {tuple(r[:5]): r[5:] for r in table_rows(table)}
    expected = {
        ("optimized", "random20", "none", "96x72", "–"): (BRUTE, BRUTE),
        ("optimized", "random20", "bvh", "96x72", "binary"): (BVH, BVH),
        ("optimized", "random20", "bvh", "96x72", "wide"): (WIDE, BVH),
        ("original", "random20", "bvh", "96x72", "grid"): (LONE, None),
    }
    assert set(rows) == set(expected)
    for key, (config, default) in expected.items():
        n, ms, _ci, speedup = rows[key]
        assert n == "3" and ms == f"{median_gpu_ms(config):.3f}", key
        assert speedup == ("–" if default is None else f"{median_gpu_ms(default) / median_gpu_ms(config):.2f}"), key
    with (report / "data/gpu_variants.csv").open() as f:
        data = {(r["accel"], r["gpu_bvh"], r["stage"]): r for r in csv.DictReader(f)}
    wide = data[("bvh", "wide", "optimized")]
    assert float(wide["speedup_over_default"]) == pytest.approx(median_gpu_ms(BVH) / median_gpu_ms(WIDE), rel=1e-12)
    readme = (report / "README.md").read_text()
    section = readme.split("## GPU traversal variants\n", 1)[1].split("\n## ", 1)[0]
    assert "gpu_ms" in section and len(table_rows(section)) == 4


def test_mrays_per_second_of_the_gpu_divides_by_gpu_ms(report):
    rows = {(r[2], r[3]): r for r in table_rows((report / "tables/summary.md").read_text())}
    rate = statistics.median(r / ms / 1000 for r, ms in zip(RAYS[WARMUP:], GPU_MS[BVH][WARMUP:]))
    assert rows[("gpu", "bvh")][-1] == f"{rate:.3g}"
    assert rows[("gpu", "bvh wide")][-1] == "–"
    with (report / "data/summary.csv").open() as f:
        data = {(r["accel"], r["gpu_bvh"]): r for r in csv.DictReader(f) if r["renderer"] == "gpu"}
    counted = data[("bvh", "binary")]
    assert float(counted["mrays_per_s"]) == pytest.approx(rate, rel=1e-12) and counted["mrays_time"] == "gpu_ms"
    summary_notes = (report / "tables/summary.md").read_text()
    assert "For the gpu renderer Mrays/s divides by gpu_ms" in summary_notes
    how = (report / "README.md").read_text().split("## How to read this report", 1)[1].split("\n## ", 1)[0]
    assert "divides by gpu_ms" in how and "`bvh wide`" in how


def test_the_gpu_counters_are_in_the_lane_occupancy_section(report):
    table = (report / "tables/lane-occupancy.md").read_text()
    assert "GPU's subgroups" in table and "a subgroup's invocations" in table
    (row,) = table_rows(table)
    assert row[3:5] == ["gpu", "bvh"]
    # 1 - (100 + 10 + 16) / (320 + 64 + 32), per frame and so summed.
    assert row[-4:] == ["31.2%", "15.6%", "50.0%", f"{100 * (1 - 126 / 416):.1f}%"]
    readme = (report / "README.md").read_text()
    assert "On the GPU a subgroup (a warp) runs its invocations in lockstep" in readme


def test_the_thesis_tables_show_the_default_variant(report):
    (table,) = [p for p in (report / "tables").glob("table4-*.md")]
    (row,) = table_rows(table.read_text())
    # gpu is the last column of table 4; 5.500 = BRUTE's median render_ms (the retired persistent one's is 7.500).
    assert row[0] == "random20" and row[-1] == "5.500"


def test_without_variants_there_is_no_gpu_section(tmp_path):
    run = write_run_dir(
        tmp_path / "run",
        {SEQUENTIAL: TIMES[SEQUENTIAL], BVH: TIMES[BVH]},
        warmup=WARMUP,
        counters={BVH: {"gpu_ms": GPU_MS[BVH]}},
    )
    out = tmp_path / "report"
    assert report_writer.main([str(run), "-o", str(out), "-q"]) == 0
    readme = (out / "README.md").read_text()
    assert "GPU traversal variants" not in readme and "divides by gpu_ms" not in readme
    assert not (out / "tables/gpu-variants.md").exists() and not (out / "data/gpu_variants.csv").exists()
    assert "| gpu | bvh |" in (out / "tables/summary.md").read_text()
