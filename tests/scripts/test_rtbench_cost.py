"""Cost vs spheres: the fitted exponent k of median render_ms = c N^k, on a run
directory written here whose frame times follow known power laws, through
the loader and the report."""

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from rtbench import atomic, load, metrics, names, plots, report_writer, tables

sys.path.insert(0, str(Path(__file__).parent / "fixtures"))
import make_thesis_run as fixture

COUNTS = (10, 100, 1000, 10000)
# (renderer, accel) -> (c, k): the run's medians are exactly c N^k.
LAWS = {
    ("simd_tbb", names.BRUTE_FORCE): (0.002, 1.0),
    ("simd_tbb", names.BVH): (0.4, 0.3),
    (names.reference_renderer(), names.BVH): (0.01, 0.55),
}
# Run on two sphere counts only: too few to fit.
TWO_COUNTS = ("tbb_only", names.BRUTE_FORCE)


def write_power_law_run(out: Path) -> None:
    cells = [(*key, n, c * n**k) for key, (c, k) in LAWS.items() for n in COUNTS]
    cells += [(*TWO_COUNTS, n, 0.01 * n) for n in COUNTS[:2]]
    runs = []
    for rep in range(2):
        for renderer, accel, n, ms in cells:
            row = fixture.config_row(f"random{n}", renderer, "optimized", accel)
            config = f"random{n}-{renderer}-{accel}"
            runs.append(fixture.write_run(out, len(runs), config, rep, row, fixture.frame_times(ms, rep, False), n))
    fixture.write_manifest(out, runs, "power-laws")


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    """The report's parts that concern the cost vs spheres (the whole report
    is test_report's; its other figures would double this test's time)."""
    run = tmp_path_factory.mktemp("power-laws")
    write_power_law_run(run)
    inputs = report_writer.gather([run])
    results = report_writer.compute(inputs)
    out = run / "report"
    figures = {
        "cost_vs_spheres": plots.cost_vs_spheres(results.curves, results.cost_fits, out / "plots/cost_vs_spheres")
    }
    (table,) = [t for t in results.tables if t.slug == "cost-vs-spheres"]
    assert len(table.align) == len(table.headers) and all(len(row) == len(table.headers) for row in table.rows)
    atomic.write_text(out / "tables/cost-vs-spheres.md", tables.to_markdown(table))
    report_writer.write_data(inputs, results, out / report_writer.DATA_DIR)
    atomic.write_text(out / "README.md", report_writer.readme(inputs, results, figures, out))
    return results, out


def test_fitted_exponents_are_the_known_ones(report):
    results, _ = report
    fits = results.cost_fits.set_index([names.RENDERER, names.ACCEL])
    assert sorted(fits.index) == sorted(LAWS)  # not the configuration with two sphere counts
    for key, (c, k) in LAWS.items():
        fit = fits.loc[key]
        assert fit["exponent"] == pytest.approx(k, abs=1e-9)
        assert fit["coefficient"] == pytest.approx(c, rel=1e-9)
        assert fit["r2"] == pytest.approx(1.0)
        assert (fit["counts"], fit["spheres_min"], fit["spheres_max"]) == (len(COUNTS), COUNTS[0], COUNTS[-1])


def test_the_report_has_the_table_the_data_and_the_plot(report):
    _, out = report
    for fmt in ("png", "svg"):
        assert (out / f"plots/cost_vs_spheres.{fmt}").stat().st_size > 0
    assert (out / "plots/cost_vs_spheres.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    table = (out / "tables/cost-vs-spheres.md").read_text()
    for (renderer, accel), (_, k) in LAWS.items():
        row = next(line for line in table.splitlines() if line.startswith(f"| optimized | {renderer} | {accel} |"))
        assert f"| {k:.2f} |" in row and f"{COUNTS[0]}–{COUNTS[-1]}" in row
    readme = (out / "README.md").read_text()
    assert "## Cost vs spheres" in readme and "plots/cost_vs_spheres.png" in readme
    assert "No cost-vs-spheres figure" not in readme
    assert len((out / "data/cost_vs_spheres.csv").read_text().splitlines()) == len(LAWS) + 1


def test_runs_without_load_times_have_no_startup_table(report):
    """Sidecars from before the load time was recorded (this fixture's) load,
    and the report leaves the table out rather than showing it empty."""
    results, out = report
    assert not any(t.slug == "startup-vs-spheres" for t in results.tables)
    assert "Before the first frame" not in (out / "README.md").read_text()


def test_load_and_build_times_are_reported_per_scene(tmp_path):
    """Each sidecar given load and build times that grow with N: the table's
    medians are those of the runs, one row per scene and accel."""
    run = tmp_path / "power-laws"
    write_power_law_run(run)
    for meta_path in (run / load.FRAMES_DIR).glob(f"*{load.META_SUFFIX}"):
        meta = json.loads(meta_path.read_text())
        n = meta["scene"]["spheres"]
        rep = int(meta_path.name.split("-r")[-1][0])
        meta["scene"]["load_ms"] = 0.01 * n + rep  # medians: 0.01 N + 0.5
        meta["prepare_ms"] = 0.02 * n
        if meta["config"]["accel"] != names.BRUTE_FORCE:
            meta["accel_structure"] = {"kind": meta["config"]["accel"], "build_ms": 0.003 * n, "nodes": 1, "depth": 1}
        atomic.write_json(meta_path, meta)
    inputs = report_writer.gather([run])
    results = report_writer.compute(inputs)
    (table,) = [t for t in results.tables if t.slug == "startup-vs-spheres"]
    rows = {(r[1], r[2]): r for r in table.rows}
    assert len(rows) == 2 * len(COUNTS)  # brute force and the BVH at every count
    for n in COUNTS:
        brute, bvh = rows[(str(n), names.BRUTE_FORCE)], rows[(str(n), names.BVH)]
        assert brute[4] == tables.fmt_ms(0.01 * n + 0.5) and brute[5] == tables.MISSING
        assert bvh[5] == tables.fmt_ms(0.003 * n) and bvh[6] == tables.fmt_ms(0.02 * n)
    readme = report_writer.readme(inputs, results, {}, run / "report")
    assert "Before the first frame" in readme


def test_power_law_fit_of_noisy_times_and_too_few_points():
    rng = np.random.default_rng(3)
    n = np.geomspace(10, 1e5, 9)
    k, c, r2 = metrics.power_law_fit(n, 0.05 * n**0.7 * rng.lognormal(0.0, 0.05, n.size))
    assert k == pytest.approx(0.7, abs=0.05) and c == pytest.approx(0.05, rel=0.5) and 0.95 < r2 <= 1.0
    assert all(math.isnan(v) for v in metrics.power_law_fit([100, 100], [1.0, 2.0]))


def test_the_corpus_scenes_lie_on_no_curve():
    """ground500, crowd1000 and clusters10000 are three sphere counts of one
    configuration, but three layouts: neither a curve of their own nor points
    on the random scenes' curve."""
    import pandas as pd

    counts = {"random10": 10, "random100": 100, "random1000": 1000, "ground500": 500}
    counts |= {"crowd1000": 1000, "clusters10000": 10000}
    rows = [
        {**dict.fromkeys(metrics.CURVE_KEYS, "same"), names.SCENE: scene, names.SPHERES: n, "median": 0.01 * n}
        for scene, n in counts.items()
    ]
    curves = metrics.sphere_curves(pd.DataFrame(rows))
    assert list(curves[names.SCENE]) == ["random10", "random100", "random1000"]
    assert set(curves[metrics.CURVE]) == {0}
