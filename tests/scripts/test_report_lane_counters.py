"""The report of runs with --counters: the Mrays/s column and the lane-occupancy
section, their numbers checked against ones computed here from the counts the
synthetic run was given; and neither of them in a report of runs without counters."""

from __future__ import annotations

import csv
import statistics
from pathlib import Path

import pytest
from synthetic_runs import SyntheticConfig, table_rows, write_run_dir

from rtbench import names, report_writer

PACKET = SyntheticConfig(renderer="simd_tbb", stage="optimized", accel="bvh", traversal="packet")
SINGLE = SyntheticConfig(renderer="simd_tbb", stage="optimized", accel="bvh", traversal="single")
BRUTE = SyntheticConfig(renderer="simd_only", threads=1, stage="original")
UNCOUNTED = SyntheticConfig(renderer="sequential", threads=1, lanes=1, stage="optimized")
WARMUP = 1
# Render times of two repetitions, the first frame of each a warm-up frame.
TIMES = {
    PACKET: [[50.0, 10.0, 12.0, 8.0], [50.0, 11.0, 9.0, 10.0]],
    SINGLE: [[50.0, 20.0, 16.0, 25.0], [50.0, 18.0, 22.0, 19.0]],
    BRUTE: [[90.0, 40.0, 44.0, 42.0], [90.0, 41.0, 43.0, 45.0]],
    UNCOUNTED: [[90.0, 60.0, 61.0, 62.0], [90.0, 63.0, 64.0, 65.0]],
}


def counts(rays, depth1, nodes, node_slots, node_active, spheres, sphere_slots, sphere_active, shade, shade_active):
    """Per-frame counter columns (4 frames, the same in both repetitions)."""
    return {
        "rays": rays,
        "rays_per_depth": [f"{r - d}/{d}" for r, d in zip(rays, depth1)],
        "node_visits": nodes,
        "node_lane_slots": node_slots,
        "node_lanes_active": node_active,
        "sphere_tests": spheres,
        "sphere_lane_slots": sphere_slots,
        "sphere_lanes_active": sphere_active,
        "shade_lane_slots": shade,
        "shade_lanes_active": shade_active,
    }


COUNTS = {
    PACKET: counts(
        [999, 480_000, 500_000, 520_000],
        [0, 80_000, 100_000, 120_000],
        [9, 30_000, 31_000, 32_000],
        [144, 480_000, 496_000, 512_000],
        [100, 300_000, 250_000, 200_000],
        [9, 20_000, 21_000, 22_000],
        [144, 320_000, 336_000, 352_000],
        [100, 100_000, 110_000, 120_000],
        [160, 30_000, 31_250, 32_500],
        [10, 25_000, 26_000, 27_000],
    ),
    SINGLE: counts(
        [999, 480_000, 500_000, 520_000],
        [0, 80_000, 100_000, 120_000],
        [9, 90_000, 95_000, 99_000],
        [72, 720_000, 760_000, 792_000],
        [70, 500_000, 520_000, 560_000],
        [9, 40_000, 41_000, 42_000],
        [72, 320_000, 328_000, 336_000],
        [70, 90_000, 95_000, 99_000],
        [160, 30_000, 31_250, 32_500],
        [10, 25_000, 26_000, 27_000],
    ),
    # Brute force: no node visits, so no node occupancy.
    BRUTE: counts(
        [999, 400_000, 410_000, 420_000],
        [0, 50_000, 60_000, 70_000],
        [0, 0, 0, 0],
        [0, 0, 0, 0],
        [0, 0, 0, 0],
        [9, 2_500_000, 2_600_000, 2_700_000],
        [144, 40_000_000, 41_600_000, 43_200_000],
        [100, 30_000_000, 31_000_000, 32_000_000],
        [160, 25_000, 25_625, 26_250],
        [10, 20_000, 21_000, 22_000],
    ),
}
KINDS = [
    ("node_lane_slots", "node_lanes_active"),
    ("sphere_lane_slots", "sphere_lanes_active"),
    ("shade_lane_slots", "shade_lanes_active"),
]


def expected(config) -> dict:
    """The report's numbers for one configuration, from the counts above
    (measured frames only: every frame but the first of each repetition)."""
    c = COUNTS[config]
    reps = len(TIMES[config])
    total = {k: sum(c[k][WARMUP:]) * reps for k in c if k != "rays_per_depth"}
    frames = (len(c["rays"]) - WARMUP) * reps
    occupancy = [total[active] / total[slots] if total[slots] else None for slots, active in KINDS]
    masked = 1 - sum(total[a] for _, a in KINDS) / sum(total[s] for s, _ in KINDS)
    rates = [r / ms / 1000 for rep in TIMES[config] for r, ms in zip(c["rays"][WARMUP:], rep[WARMUP:])]
    return {
        "rays_per_frame": total["rays"] / frames,
        "node_visits_per_frame": total["node_visits"] / frames,
        "occupancy": occupancy,
        "masked": masked,
        "mrays": statistics.median(rates),
    }


def percent(x) -> str:
    return "–" if x is None else f"{100 * x:.1f}%"


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    base = tmp_path_factory.mktemp("counters")
    run = write_run_dir(base / "run", TIMES, warmup=WARMUP, counters=COUNTS)
    out = base / "report"
    assert report_writer.main([str(run), "-o", str(out), "-q"]) == 0
    return out


def test_the_occupancy_table_has_one_row_per_counted_configuration_with_the_counts_numbers(report):
    table = (report / "tables/lane-occupancy.md").read_text()
    rows = {(r[0], r[3], r[4]): r for r in table_rows(table)}
    assert set(rows) == {
        ("optimized", "simd_tbb", "bvh"),
        ("optimized", "simd_tbb", "bvh single"),
        ("original", "simd_only", "none"),
    }
    for config, key in ((PACKET, "bvh"), (SINGLE, "bvh single"), (BRUTE, "none")):
        row = rows[(config.stage, config.renderer, key)]
        want = expected(config)
        exits = names.EARLY_EXIT_SEPARATOR.join(names.STAGES[config.stage]["early_exits"]) or names.NO_EARLY_EXIT
        assert row[1] == exits
        assert row[-6:] == [
            str(round(want["rays_per_frame"])),
            str(round(want["node_visits_per_frame"])),
            *(percent(x) for x in want["occupancy"]),
            percent(want["masked"]),
        ], key


def test_the_occupancy_data_keep_full_precision(report):
    with (report / "data/lane_occupancy.csv").open() as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 3
    by_traversal = {(r[names.RENDERER], r[names.TRAVERSAL]): r for r in rows}
    for config in (PACKET, SINGLE, BRUTE):
        row = by_traversal[(config.renderer, config.traversal)]
        assert float(row["masked_share"]) == pytest.approx(expected(config)["masked"], rel=1e-12)
        assert int(row[names.RAYS]) == sum(COUNTS[config]["rays"][WARMUP:]) * 2
        assert int(row["frames"]) == 6


def test_the_readme_states_the_hypothesis_above_the_table_with_this_runs_range(report):
    readme = (report / "README.md").read_text()
    section = readme.split("## Lane occupancy (the thesis' masking waste, measured)\n", 1)[1].split("\n## ", 1)[0]
    statement, table = section.split("**Lane occupancy", 1)
    assert "masked lanes do wasted work" in statement and "docs/thesis.md" in statement
    shares = {config: expected(config)["masked"] for config in (PACKET, SINGLE, BRUTE)}
    mostly = sum(share > 0.5 for share in shares.values())
    assert f"Here {mostly} of 3 configurations mask off more than 50%" in statement
    # Each configuration's label as the report's warnings write it.
    labels = {
        PACKET: "random20/simd_tbb/optimized/t2/l16/bvh",
        SINGLE: "random20/simd_tbb/optimized/t2/l16/bvh/single",
        BRUTE: "random20/simd_only/original/l16",
    }
    low, high = min(shares, key=shares.get), max(shares, key=shares.get)
    assert f"from {percent(shares[low])} ({labels[low]}) to {percent(shares[high])} ({labels[high]})" in statement
    assert len(table_rows(table)) == 3  # the table follows the statement


def test_mrays_per_second_is_a_summary_column_where_counters_ran(report):
    table = (report / "tables/summary.md").read_text()
    header = next(line for line in table.splitlines() if line.startswith("| stage"))
    assert header.rstrip(" |").endswith("Mrays/s")
    rows = {(r[2], r[3]): r for r in table_rows(table)}
    for config, accel in ((PACKET, "bvh"), (SINGLE, "bvh single"), (BRUTE, "none")):
        rate = expected(config)["mrays"]
        assert rows[(config.renderer, accel)][-1] == (f"{rate:.0f}" if rate >= 100 else f"{rate:.3g}")
    assert rows[("sequential", "none")][-1] == "–"
    with (report / "data/summary.csv").open() as f:
        data = {(r[names.RENDERER], r[names.TRAVERSAL]): r for r in csv.DictReader(f)}
    assert float(data[("simd_tbb", "single")]["mrays_per_s"]) == pytest.approx(expected(SINGLE)["mrays"], rel=1e-12)
    assert data[("sequential", "")]["mrays_per_s"] == ""


def test_how_to_read_explains_mrays_and_the_traversal_in_the_accel_column(report):
    readme = (report / "README.md").read_text()
    how = readme.split("## How to read this report", 1)[1].split("\n## ", 1)[0]
    assert "**Mrays/s**" in how and "rays / render_ms / 1000" in how
    assert "`bvh single`" in how


def test_without_counters_there_is_no_occupancy_section_and_no_mrays_column(tmp_path):
    run = write_run_dir(tmp_path / "run", {PACKET: TIMES[PACKET], SINGLE: TIMES[SINGLE]}, warmup=WARMUP)
    out = tmp_path / "report"
    assert report_writer.main([str(run), "-o", str(out), "-q"]) == 0
    readme = (out / "README.md").read_text()
    assert "Lane occupancy" not in readme and "Mrays/s" not in readme
    assert not (out / "tables/lane-occupancy.md").exists() and not (out / "data/lane_occupancy.csv").exists()
    assert "Mrays/s" not in (out / "tables/summary.md").read_text()
    assert "mrays_per_s" not in (out / "data/summary.csv").read_text()
    # The traversal still names its configuration.
    assert "| bvh single |" in (out / "tables/summary.md").read_text()


def test_a_stale_occupancy_table_goes_when_a_report_without_counters_replaces_it(report, tmp_path):
    out = tmp_path / "report"
    run = write_run_dir(tmp_path / "run", {UNCOUNTED: TIMES[UNCOUNTED]}, warmup=WARMUP)
    for part in ("tables", "data"):
        (out / part).mkdir(parents=True)
    (out / "tables/lane-occupancy.md").write_text((report / "tables/lane-occupancy.md").read_text())
    (out / "data/lane_occupancy.csv").write_text((report / "data/lane_occupancy.csv").read_text())
    assert report_writer.main([str(run), "-o", str(out), "-q"]) == 0
    assert not (out / "tables/lane-occupancy.md").exists() and not (out / "data/lane_occupancy.csv").exists()


def test_the_report_reads_a_run_without_counters_next_to_one_with_them(tmp_path):
    """Pooled directories: the counted configuration gets its numbers, the other a dash."""
    counted = write_run_dir(tmp_path / "a", {PACKET: TIMES[PACKET]}, warmup=WARMUP, counters={PACKET: COUNTS[PACKET]})
    plain = write_run_dir(tmp_path / "b", {UNCOUNTED: TIMES[UNCOUNTED]}, warmup=WARMUP)
    out = tmp_path / "report"
    assert report_writer.main([str(counted), str(plain), "-o", str(out), "-q"]) == 0
    rows = table_rows((out / "tables/lane-occupancy.md").read_text())
    assert [r[3] for r in rows] == ["simd_tbb"]
    assert Path(out / "tables/summary.md").read_text().count("| – |") >= 1
