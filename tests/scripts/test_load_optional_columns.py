"""The frame CSV's optional columns (names.OPTIONAL_COLUMNS: traversal,
hybrid_threshold and the --counters columns): CSVs written before them load as
runs without a traversal or counters, CSVs with them load with their types, and
values that cannot be right stop the loader with an error naming the file."""

import csv
import io
import shutil
from pathlib import Path

import pandas as pd
import pytest
from synthetic_runs import SyntheticConfig, write_run_dir

from rtbench import load, names

FIXTURE = Path(__file__).parent / "fixtures" / "thesis-run"
ONE = "frames/random100-simd_tbb-optimized-r0"
BVH_SINGLE = SyntheticConfig(accel="bvh", traversal="single")
HYBRID = SyntheticConfig(accel="bvh", traversal="hybrid", hybrid_threshold=5)
# Four frames (one warm-up) of counts chosen by hand: rays_per_depth adds up to rays.
COUNTS = {
    "rays": [100, 110, 120, 130],
    "rays_per_depth": ["80/20", "90/20", "100/20", "100/30"],
    "node_visits": [40, 41, 42, 43],
    "node_lane_slots": [640, 656, 672, 688],
    "node_lanes_active": [100, 101, 102, 103],
    "sphere_tests": [7, 8, 9, 10],
    "sphere_lane_slots": [112, 128, 144, 160],
    "sphere_lanes_active": [50, 51, 52, 53],
    "shade_lane_slots": [32, 32, 32, 32],
    "shade_lanes_active": [20, 21, 22, 23],
}
TIMES = [[9.0, 5.0, 5.5, 6.0]]


def test_a_csv_without_the_optional_columns_loads_without_traversal_or_counters():
    header = (FIXTURE / f"{ONE}.csv").read_text().splitlines()[0].split(",")
    assert not set(names.OPTIONAL_COLUMNS) & set(header)  # the fixture is such a CSV
    frames = load.load_runs([FIXTURE])
    assert set(frames[names.TRAVERSAL]) == {""}
    for column in names.OPTIONAL_COLUMNS:
        if names.COLUMN_TYPES[column] == "int":
            assert frames[column].dtype == "Int64" and frames[column].isna().all(), column
    assert set(frames[names.RAYS_PER_DEPTH]) == {""}


def test_an_older_csv_of_the_simd_kernel_on_the_bvh_walked_packets(tmp_path):
    run = tmp_path / "run"
    shutil.copytree(FIXTURE, run)
    for suffix in (".csv", ".meta.json"):
        path = run / f"{ONE}{suffix}"
        path.write_text(path.read_text().replace(",none,800,", ",bvh,800,").replace('"none"', '"bvh"'))
    frames = load.load_runs([run])
    edited = frames[names.SOURCE] == f"run/{ONE}.csv"
    assert set(frames.loc[edited, names.TRAVERSAL]) == {names.PACKET}
    assert set(frames.loc[~edited, names.TRAVERSAL]) == {""}


def test_counter_columns_load_as_integers(tmp_path):
    write_run_dir(tmp_path, {HYBRID: TIMES}, counters={HYBRID: COUNTS})
    frames = load.load_runs([tmp_path])
    assert list(frames[names.TRAVERSAL]) == ["hybrid"] * 4
    assert frames[names.HYBRID_THRESHOLD].dtype == "Int64" and set(frames[names.HYBRID_THRESHOLD]) == {5}
    for column, values in COUNTS.items():
        assert list(frames[column]) == values, column
        if names.COLUMN_TYPES[column] == "int":
            assert frames[column].dtype == "Int64", column


def test_a_run_without_counters_has_empty_counter_columns(tmp_path):
    write_run_dir(tmp_path, {BVH_SINGLE: TIMES})
    frames = load.load_runs([tmp_path])
    assert frames[names.RAYS].isna().all() and frames[names.HYBRID_THRESHOLD].isna().all()
    assert set(frames[names.TRAVERSAL]) == {"single"}


def _rewrite(path: Path, edit) -> None:
    """Applies edit(row dict) to every frame row of a CSV."""
    rows = list(csv.DictReader(io.StringIO(path.read_text())))
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=list(rows[0]), lineterminator="\n")
    writer.writeheader()
    for i, row in enumerate(rows):
        edit(i, row)
        writer.writerow(row)
    path.write_text(out.getvalue())


def _set(column, value, only_frame=None):
    def edit(i, row):
        if only_frame is None or i == only_frame:
            row[column] = value

    return edit


@pytest.mark.parametrize(
    "edit, message",
    [
        (_set("traversal", "zigzag"), "column traversal: unknown value 'zigzag'"),
        (_set("hybrid_threshold", "x"), "column hybrid_threshold: 'x' is not a valid int"),
        (_set("rays", "", only_frame=2), "column rays is empty in 1 of 4 frames"),
        (_set("rays_per_depth", "80;20", only_frame=0), "rays_per_depth: '80;20' is not counts joined by '/'"),
        (_set("rays_per_depth", "80/21", only_frame=0), "rays_per_depth: '80/21' adds up to 101, not rays 100"),
        (_set("node_lanes_active", "700", only_frame=1), "line 3: node_lanes_active 700 exceeds node_lane_slots 656"),
        (_set("sphere_tests", "-1", only_frame=1), "column sphere_tests: a negative count"),
    ],
)
def test_impossible_counter_or_traversal_values_name_the_file(tmp_path, edit, message):
    write_run_dir(tmp_path, {HYBRID: TIMES}, counters={HYBRID: COUNTS})
    (path,) = tmp_path.glob("frames/*.csv")
    _rewrite(path, edit)
    with pytest.raises(load.RunDataError) as e:
        load.load_runs([tmp_path])
    assert str(e.value).startswith(str(path)) and message in str(e.value)


def test_a_threshold_without_traversal_hybrid_is_refused(tmp_path):
    write_run_dir(tmp_path, {BVH_SINGLE: TIMES})
    (path,) = tmp_path.glob("frames/*.csv")
    _rewrite(path, _set("hybrid_threshold", "4"))
    with pytest.raises(load.RunDataError, match="hybrid_threshold: 4 with traversal single"):
        load.load_runs([tmp_path])


@pytest.mark.parametrize(
    "header_edit, message",
    [
        (lambda h: [c for c in h if c != names.RENDER_MS], "missing render_ms"),
        (lambda h: [c for c in h if c != names.RAYS] + [names.RAYS], "columns out of order"),
        (lambda h: [*h, "lane_bogus"], "unexpected lane_bogus"),
    ],
)
def test_only_optional_columns_may_be_missing_and_order_still_counts(tmp_path, header_edit, message):
    write_run_dir(tmp_path, {HYBRID: TIMES}, counters={HYBRID: COUNTS})
    (path,) = tmp_path.glob("frames/*.csv")
    table = pd.read_csv(path, dtype=str, keep_default_na=False)
    columns = header_edit(list(table.columns))
    table.reindex(columns=columns, fill_value="0").to_csv(path, index=False)
    with pytest.raises(load.RunDataError, match="header does not match") as e:
        load.load_runs([tmp_path])
    assert message in str(e.value)


def test_a_csv_with_some_optional_columns_left_out_loads(tmp_path):
    """Any subset of the optional columns may be missing (in schema order otherwise)."""
    write_run_dir(tmp_path, {HYBRID: TIMES}, counters={HYBRID: COUNTS})
    (path,) = tmp_path.glob("frames/*.csv")
    table = pd.read_csv(path, dtype=str, keep_default_na=False)
    table.drop(columns=[c for c in names.COUNTER_COLUMNS]).to_csv(path, index=False)
    frames = load.load_runs([tmp_path])
    assert set(frames[names.TRAVERSAL]) == {"hybrid"} and frames[names.RAYS].isna().all()
