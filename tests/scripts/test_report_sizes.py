"""The report of a run that mixes image sizes and thread counts, as the GPU
machine's reference run does (the gpu renderer also at a larger size, the
scaling points on one scene only): every table and figure says which size
a number is for, and no figure draws a bar or a legend entry for a
configuration that is not in its panel."""

import warnings

import pytest
from synthetic_runs import SyntheticConfig, write_run_dir

from rtbench import plots, report_writer, tables

SMALL, LARGE = (96, 72), (192, 144)


@pytest.fixture(scope="module")
def mixed_run(tmp_path_factory):
    cpu = SyntheticConfig(renderer="sequential", threads=1, lanes=1)
    wide = SyntheticConfig(renderer="simd_tbb", threads=2, lanes=16)
    runs = {
        cpu: [[9.0, 8.0, 8.1]],
        wide: [[2.0, 1.0, 1.1]],
        SyntheticConfig(renderer="simd_tbb", threads=1, lanes=16): [[3.0, 2.0, 2.1]],  # a scaling point
        SyntheticConfig(scene="default", renderer="sequential", threads=1, lanes=1): [[5.0, 4.0, 4.1]],
        SyntheticConfig(renderer="sequential", threads=1, lanes=1, stage="single-pass"): [[9.5, 8.5, 8.6]],
        SyntheticConfig(renderer="gpu", threads=0, lanes=0): [[0.6, 0.5, 0.51]],
        SyntheticConfig(renderer="gpu", threads=0, lanes=0, width=LARGE[0], height=LARGE[1]): [[1.6, 1.5, 1.52]],
    }
    return write_run_dir(tmp_path_factory.mktemp("run") / "20260101T000000Z-mixed", runs)


def test_thesis_tables_name_their_size_and_the_empty_ones_are_left_out(mixed_run):
    inputs = report_writer.gather([mixed_run])
    results = report_writer.compute(inputs)
    mirrors = {t.slug: t for t in results.tables if t.slug.startswith("table")}
    small, large = (f"{w}x{h}" for w, h in (SMALL, LARGE))
    # Stages single-pass and optimized ran at the small size; at the large one only the gpu, optimized.
    assert {slug for slug in mirrors if slug.endswith(small)} == {
        f"table3-single-pass-{small}",
        f"table4-optimized-{small}",
    }
    assert {slug for slug in mirrors if slug.endswith(large)} == {f"table4-optimized-{large}"}
    readme = report_writer.readme(inputs, results, {}, mixed_run)
    assert "none of their renderers ran at their stage in this run: tables 1 (original: " in readme
    assert "**Table 3 (single-pass), 96x72: render time per frame [ms]**" in readme
    assert mirrors[f"table4-optimized-{large}"].title.startswith(f"Table 4 (optimized), {large}:")
    # Its gpu column is the large size's median (1.50 and 1.52 measured), not the small one's.
    assert [row[-1] for row in mirrors[f"table4-optimized-{large}"].rows] == ["–", "1.510"]
    assert [row[-1] for row in mirrors[f"table4-optimized-{small}"].rows] == ["–", "0.505"]


def test_render_bars_show_each_size_once_and_the_widest_configuration(mixed_run):
    summary = report_writer.compute(report_writer.gather([mixed_run])).summary
    labels = sorted(plots.bar_rows(summary)["_label"])
    assert labels == sorted(["sequential 96x72"] * 3 + ["simd_tbb t2 l16 96x72", "gpu 96x72", "gpu 192x144"])


def test_figures_of_a_mixed_run_draw_without_numpy_warnings(mixed_run, tmp_path):
    """A configuration absent from a panel (the scaling point on one scene,
    the gpu's second size) used to become an all-NaN bar, which numpy warns
    about while matplotlib sizes its error bars."""
    inputs = report_writer.gather([mixed_run])
    results = report_writer.compute(inputs)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        figures = report_writer.draw_figures(inputs, results, tmp_path)
    assert figures["render_ms"] and figures["frame_series"] and figures["distributions"]
    assert tables.sizes(results.summary)[0] == SMALL
