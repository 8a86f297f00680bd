"""Speedup and Karp-Flatt, with the thesis' own table as the known answer."""

import math

import pytest

from rtbench import metrics, thesis


def test_karp_flatt_formula():
    assert metrics.karp_flatt(2.0, 2) == pytest.approx(0.0)  # perfect scaling
    assert metrics.karp_flatt(1.0, 4) == pytest.approx(1.0)  # no speedup: all serial
    assert metrics.karp_flatt(3.0, 4) == pytest.approx((1 / 3 - 1 / 4) / (1 - 1 / 4))
    assert math.isnan(metrics.karp_flatt(1.5, 1))
    assert math.isnan(metrics.speedup(0.0, 1.0))


@pytest.fixture(scope="module")
def published():
    return thesis.reported_vs_recomputed(thesis.load_tables(), thesis.load_reported())


def _row(df, stage, renderer):
    return df[(df["stage"] == stage) & (df["renderer"] == renderer) & (df["scene"] == "random100")].iloc[0]


def test_thesis_speedups_follow_from_its_table(published):
    assert _row(published, "optimized", "simd_tbb")["speedup_recomputed"] == pytest.approx(5.956, abs=5e-4)
    assert _row(published, "original", "simd_tbb")["speedup_recomputed"] == pytest.approx(1.595, abs=5e-4)
    assert _row(published, "original", "gpu")["speedup_recomputed"] == pytest.approx(742.735, abs=5e-4)
    for r in published.itertuples():
        assert r.speedup_recomputed == pytest.approx(r.speedup_reported, rel=1e-3)


def test_thesis_karp_flatt_recomputed_differs_from_reported(published):
    opt, orig = _row(published, "optimized", "simd_tbb"), _row(published, "original", "simd_tbb")
    assert opt["p"] == 32
    assert opt["karp_flatt_recomputed"] == pytest.approx(0.141, abs=5e-4)
    assert opt["karp_flatt_reported"] == pytest.approx(0.206)
    assert orig["karp_flatt_recomputed"] == pytest.approx(0.615, abs=5e-4)
    assert orig["karp_flatt_reported"] == pytest.approx(0.680)
    assert _row(published, "original", "gpu")["karp_flatt_recomputed"] == pytest.approx(0.00037, abs=5e-6)


def test_table_layout_comes_from_the_thesis_data():
    layout = thesis.table_layout(thesis.load_tables())
    assert [(t.number, t.stage) for t in layout] == [
        (1, "original"),
        (2, "original"),
        (3, "single-pass"),
        (4, "optimized"),
    ]
    assert layout[1].renderers == ("simd_only", "tbb_only")
    assert layout[0].scenes == ("default", "random20", "random100")


def test_processors_from_metadata_and_gpu_estimates():
    est = metrics.load_gpu_estimates()
    # A CPU renderer's p comes from its configuration even where it presented on a device.
    assert metrics.processors("simd_tbb", 2, 16, "Apple M1", 2, est) == (32.0, "threads x lanes")
    assert metrics.processors("sequential", 1, 1, "", 2, est)[0] == 1.0
    assert metrics.processors("gpu", 0, 0, "Apple M1", 8, est)[0] == 1024.0
    assert metrics.processors("gpu", 0, 0, "llvmpipe (LLVM 15.0.6, 256 bits)", 2, est)[0] == 16.0
    assert metrics.processors("gpu", 0, 0, "NVIDIA H100 PCIe", 16, est)[0] == 14592.0
    assert metrics.processors("gpu", 0, 0, "NVIDIA H100 80GB HBM3", 16, est)[0] == 16896.0
    p, why = metrics.processors("gpu", 0, 0, "Some Future GPU", 2, est)
    assert math.isnan(p) and "--gpu-p" in why
    assert metrics.processors("gpu", 0, 0, "Some Future GPU", 2, est, gpu_override=4096) == (4096.0, "--gpu-p")


def _scaling_summary():
    import pandas as pd

    from rtbench import names

    rows = []
    for threads, median in ((1, 100.0), (2, 55.0), (4, 30.0)):
        rows.append(
            {
                names.SCENE: "s",
                names.SPHERES: 3,
                names.STAGE: "optimized",
                names.ACCEL: names.BRUTE_FORCE,
                names.TRAVERSAL: "",
                names.HYBRID_THRESHOLD: None,
                **{axis: "" for axis in [*names.GPU_AXES, *names.RETIRED_GPU_AXES]},
                names.RENDERER: "tbb_only",
                names.LANES: 1,
                names.SIMD_TARGET: "",
                names.WIDTH: 8,
                names.HEIGHT: 8,
                names.DEVICE: "",
                names.BUILD_TYPE: "Release",
                names.THREADS: threads,
                "median": median,
                "ci_low": median * 0.99,
                "ci_high": median * 1.01,
            }
        )
    rows.append({**rows[0], names.RENDERER: names.reference_renderer(), "median": 100.0})
    return pd.DataFrame(rows)


def test_strong_scaling_is_relative_to_the_fewest_threads(tmp_path):
    from rtbench import plots

    scaling = metrics.scaling_table(_scaling_summary())
    assert list(scaling["threads"]) == [1, 2, 4]  # the reference has one thread count: no curve
    assert list(scaling["scaling_speedup"]) == pytest.approx([1.0, 100 / 55, 100 / 30])
    assert list(scaling["efficiency"]) == pytest.approx([1.0, 100 / 55 / 2, 100 / 30 / 4])
    written = plots.speedup_vs_threads(scaling, tmp_path / "scaling")
    assert [p.suffix for p in written] == [".png", ".svg"] and all(p.stat().st_size > 0 for p in written)
    assert plots.speedup_vs_threads(scaling.iloc[0:0], tmp_path / "none") == []


def test_metrics_table_pairs_each_configuration_with_the_reference():
    table = metrics.metrics_table(_scaling_summary(), 4, metrics.load_gpu_estimates())
    assert list(table["threads"]) == [1, 2, 4]
    assert list(table["speedup"]) == pytest.approx([1.0, 100 / 55, 100 / 30])
    assert math.isnan(table["karp_flatt"].iloc[0])  # p = 1
    assert table["karp_flatt"].iloc[2] == pytest.approx(metrics.karp_flatt(100 / 30, 4))
