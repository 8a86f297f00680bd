"""Summary statistics against hand-computed answers."""

import math

import numpy as np
import pandas as pd
import pytest

from rtbench import names, noise, stats


def test_median_and_mad_of_known_arrays():
    assert stats.median([3, 1, 2]) == 2
    assert stats.median([4, 1, 3, 2]) == 2.5
    # |x - 2| = 1, 1, 0, 2, 1 -> median 1
    assert stats.mad([1, 3, 2, 4, 1]) == 1
    assert stats.mad([5, 5, 5]) == 0


def test_percentiles_interpolate_linearly():
    x = np.arange(1, 101, dtype=float)  # 1..100
    assert stats.percentile(x, 95) == pytest.approx(95.05)
    assert stats.percentile(x, 99) == pytest.approx(99.01)


def test_summarize_reports_every_statistic():
    s = stats.summarize([10.0, 12.0, 11.0, 13.0, 14.0])
    assert s["n"] == 5 and s["median"] == 12 and s["mean"] == 12
    assert s["std"] == pytest.approx(math.sqrt(2.5))
    assert s["mad"] == 1 and s["min"] == 10 and s["max"] == 14
    assert s["ci_low"] <= s["median"] <= s["ci_high"]
    assert s["outliers"] == 0


def test_bootstrap_ci_is_deterministic_and_brackets_the_median():
    rng = np.random.default_rng(1)
    x = rng.lognormal(3.0, 0.2, size=40)
    a, b = stats.bootstrap_median_ci(x), stats.bootstrap_median_ci(x)
    assert a == b
    assert a[0] < np.median(x) < a[1]
    assert stats.bootstrap_median_ci(x, seed=99) != a
    assert stats.bootstrap_median_ci([7.0]) == (7.0, 7.0)


def test_modified_z_flags_a_spike_and_keeps_it():
    x = [10.0, 10.1, 9.9, 10.05, 9.95, 50.0]
    z = stats.modified_z_scores(x)
    # median 10.025, MAD 0.075 -> z(50) = 0.6745 * 39.975 / 0.075
    assert z[-1] == pytest.approx(0.6745 * 39.975 / 0.075)
    assert list(stats.outlier_mask(x)) == [False] * 5 + [True]
    assert stats.summarize(x)["n"] == 6  # flagged, never dropped


def test_modified_z_with_zero_mad_flags_only_values_off_the_median():
    assert list(stats.outlier_mask([1.0, 1.0, 1.0, 2.0])) == [False, False, False, True]


def _frames(values_by_rep, warmup_value=100.0):
    rows = []
    for rep, values in enumerate(values_by_rep):
        for frame, v in enumerate([warmup_value, *values]):
            rows.append(
                {
                    names.SCENE: "s",
                    names.SPHERES: 3,
                    names.RENDERER: names.reference_renderer(),
                    names.STAGE: "optimized",
                    names.ALGORITHM: "single-pass",
                    names.EARLY_EXIT: "bounce",
                    names.ACCEL: "none",
                    names.TRAVERSAL: "",
                    names.HYBRID_THRESHOLD: None,
                    **{axis: "" for axis in [*names.GPU_AXES, *names.RETIRED_GPU_AXES]},
                    names.PRECISION: names.F32,
                    names.THREADS: 1,
                    names.LANES: 1,
                    names.SIMD_TARGET: "",
                    names.GRAIN: 0,
                    names.PARTITION: "",
                    names.WIDTH: 8,
                    names.HEIGHT: 8,
                    names.DEVICE: "",
                    names.BUILD_TYPE: "Release",
                    names.FRAME: frame,
                    names.WARMUP: int(frame == 0),
                    names.REPETITION: rep,
                    names.CONFIG_ID: "c",
                    names.RENDER_MS: v,
                }
            )
    return pd.DataFrame(rows)


def test_warmup_frames_never_enter_the_summary():
    summary = stats.summarize_configs(_frames([[1.0, 2.0, 3.0], [2.0, 2.0, 2.0]]))
    assert len(summary) == 1
    row = summary.iloc[0]
    assert row["n"] == 6 and row["median"] == 2.0 and row["max"] == 3.0
    assert row["repetitions"] == 2
    assert row["rep_spread"] == 0.0  # both repetitions have median 2


def test_spread_between_repetitions_is_the_cv_of_their_medians():
    summary = stats.summarize_configs(_frames([[10.0, 10.0], [12.0, 12.0]]))
    assert summary.iloc[0]["rep_spread"] == pytest.approx(np.std([10, 12], ddof=1) / 11)
    assert noise.spread_warnings({"c": summary.iloc[0]["rep_spread"]})


def test_outlier_flags_cover_measured_frames_only():
    frames = _frames([[1.0, 1.1, 0.9, 1.05, 9.0]])
    flags = stats.flag_outliers(frames)
    assert list(flags) == [False, False, False, False, False, True]
