"""End-to-end checks of the SIMD and oneTBB renderers through the binary:
what lands in the CSV and metadata, saved frames, and exit codes."""

import csv
import json
import subprocess

import pytest

SMALL = ["--width", "37", "--height", "11", "--warmup", "1", "--frames", "2", "--quiet"]


def run(raytracer, *args):
    return subprocess.run([raytracer, *map(str, args)], capture_output=True, text=True)


def read_csv(path):
    with path.open(newline="") as f:
        return list(csv.DictReader(f))


@pytest.mark.parametrize(
    ("flag", "renderer", "threads", "simd", "tbb"),
    [
        ("--simd", "simd_tbb", "2", True, True),
        ("--simd-only", "simd_only", "1", True, False),
        ("--tbb-only", "tbb_only", "2", False, True),
    ],
)
def test_csv_and_metadata_describe_the_renderer(raytracer, repo_root, tmp_path, flag, renderer, threads, simd, tbb):
    csv_path = tmp_path / "run.csv"
    extra = ["--threads", "2", "--grain", "3", "--partition", "tiles"] if tbb else []
    done = run(raytracer, flag, repo_root / "scenes/random20.json", *SMALL, *extra, "--csv", csv_path)
    assert done.returncode == 0, done.stderr
    rows = read_csv(csv_path)
    assert {r["renderer"] for r in rows} == {renderer}
    assert {r["threads"] for r in rows} == {threads}
    assert {r["grain"] for r in rows} == ({"3"} if tbb else {"0"})
    assert {r["partition"] for r in rows} == ({"tiles"} if tbb else {""})
    lanes = {r["lanes"] for r in rows}
    target = {r["simd_target"] for r in rows}
    if simd:
        assert len(target) == 1 and target != {""}
        assert int(lanes.pop()) >= 1
    else:
        assert target == {""} and lanes == {"1"}

    meta = json.loads((tmp_path / "run.meta.json").read_text())
    assert meta["config"]["renderer"] == renderer
    assert meta["config"]["grain"] == (3 if tbb else 0)
    assert meta["config"]["partition"] == ("tiles" if tbb else "")
    assert {"TBB", "hwy"} <= set(meta["libraries"])


def test_lanes_four_is_recorded(raytracer, repo_root, tmp_path):
    csv_path = tmp_path / "run.csv"
    done = run(raytracer, "--simd-only", repo_root / "scenes/default.json", *SMALL, "--lanes", "4", "--csv", csv_path)
    if done.returncode == 2 and "float lanes" in done.stderr:
        pytest.skip("this CPU's best SIMD target has fewer than 4 float lanes")
    assert done.returncode == 0, done.stderr
    assert {r["lanes"] for r in read_csv(csv_path)} == {"4"}


@pytest.mark.parametrize(
    "args",
    [
        ["--simd", "--threads", "0"],
        ["--simd", "--lanes", "5"],
        ["--simd", "--grain", "-1"],
        ["--simd", "--partition", "diagonal"],
        ["--sequential", "--lanes", "4"],
        ["--simd-only", "--threads", "4"],
    ],
)
def test_bad_parallel_options_exit_2(raytracer, repo_root, args):
    done = run(raytracer, *args, repo_root / "scenes/default.json", *SMALL)
    assert done.returncode == 2
    assert done.stderr.strip()
