"""Frame-budget statistics (rtbench.budget) on hand-computed series, and in
the report."""

import math

import pandas as pd
import pytest
from synthetic_runs import SyntheticConfig, write_run_dir

from rtbench import budget, load, report_writer

B60, B30 = budget.DEFAULT_BUDGETS_MS


def test_default_budgets_are_60_and_30_frames_per_second():
    assert (B60, B30) == (16.67, 33.33)


def test_share_over_budget_counts_frames_strictly_slower():
    series = [10.0, 20.0, 30.0, 40.0]
    assert budget.share_over(series, B60) == 0.75
    assert budget.share_over(series, B30) == 0.25
    assert budget.share_over([B60, B60], B60) == 0.0  # on the deadline is in time
    assert math.isnan(budget.share_over([], B60))


def test_longest_run_over_budget():
    assert budget.longest_run_over([20, 20, 10, 20, 20, 20, 5], B60) == 3
    assert budget.longest_run_over([20, 10, 20], B60) == 1
    assert budget.longest_run_over([1, 2, 3], B60) == 0
    assert budget.longest_run_over([40, 40, 20, 40], B30) == 2


def test_jitter_is_the_median_difference_of_consecutive_frames_within_each_run():
    assert budget.jitter([[10.0, 12.0, 11.0, 15.0]]) == 2.0  # |diffs| 2, 1, 4
    # 12 -> 20 is the boundary between two runs, not a frame-to-frame change:
    # counted, it would make the median 3 (of 2, 8, 1, 4).
    assert budget.jitter([[10.0, 12.0], [20.0, 21.0, 25.0]]) == 2.0
    assert math.isnan(budget.jitter([[5.0], [7.0]]))


def test_budget_stats_of_one_configuration():
    series = [[10.0, 20.0, 20.0], [20.0, 20.0, 30.0, 40.0]]
    row = budget.budget_stats(series, (B60, B30))
    assert row["n"] == 7 and row["median"] == 20.0 and row["max"] == 40.0
    assert row["p99"] == pytest.approx(40.0 - 0.06 * 10.0)  # linear between the two largest of 7
    assert row[budget.share_column(B60)] == pytest.approx(6 / 7)
    # 2 + 4 consecutive frames over 16.67 ms, but in two runs: the longest is 4, not 6.
    assert row[budget.run_column(B60)] == 4
    assert row[budget.share_column(B30)] == pytest.approx(1 / 7) and row[budget.run_column(B30)] == 1
    assert row["jitter"] == 10.0  # |diffs| 10, 0 | 0, 10, 10


def test_the_budget_is_for_the_whole_frame_and_warmup_frames_never_count(tmp_path):
    config = SyntheticConfig()
    # Render 16 ms is inside 16.67 ms, but with a 1 ms Present every frame misses it;
    # the 100 ms warm-up frames must not reach any statistic.
    run = write_run_dir(tmp_path / "run", {config: [[100.0, 16.0, 16.0, 16.0], [100.0, 16.0, 16.0]]}, present_ms=1.0)
    row = budget.summarize_budgets(load.load_runs([run])).iloc[0]
    assert row["n"] == 5 and row["median"] == 17.0 and row["max"] == 17.0
    assert row[budget.share_column(B60)] == 1.0 and row[budget.run_column(B60)] == 3
    assert row[budget.share_column(B30)] == 0.0 and row[budget.run_column(B30)] == 0


def test_the_report_has_the_frame_budget_table_and_data(tmp_path):
    config = SyntheticConfig()
    run = write_run_dir(tmp_path / "run", {config: [[50.0, 10.0, 20.0, 20.0, 40.0], [50.0, 20.0, 10.0, 10.0, 10.0]]})
    out = tmp_path / "report"
    assert report_writer.main([str(run), "-o", str(out), "-q", "--budget-ms", "16.67", "30"]) == 0
    readme = (out / "README.md").read_text()
    assert "## Frame budget" in readme and "| > 16.67 ms | longest run | > 30 ms | longest run |" in readme
    # 8 measured frames: 4 over 16.67 ms (longest run 3), 1 over 30 ms; jitter median of 10,0,20 | 10,0,0 = 5.
    assert "| 8 | 15.00 | 38.60 | 40.00 | 5.000 | 50.0% | 3 | 12.5% | 1 |" in readme
    data = pd.read_csv(out / "data" / "budget.csv")
    assert data[budget.share_column(30.0)].tolist() == [0.125]
    assert (out / "tables" / "frame-budget.md").is_file()
