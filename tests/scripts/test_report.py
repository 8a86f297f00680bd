"""report.py regenerates a full report from the committed fixture run (the
thesis' own published times dressed as a run), with known answers."""

import math
import os
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

from rtbench import names, report_writer, tables

FIXTURE = Path(__file__).parent / "fixtures" / "thesis-run"


def report_command(repo_root, *args):
    """scripts/report.py as a person runs it, under the Python running the tests."""
    return subprocess.run(
        [repo_root / "scripts/report.py", *args],
        capture_output=True,
        text=True,
        env={**os.environ, "RT_PYTHON": sys.executable},
    )


@pytest.fixture(scope="module")
def generated(tmp_path_factory, repo_root):
    out = tmp_path_factory.mktemp("report")
    done = report_command(repo_root, FIXTURE, "-o", out)
    assert done.returncode == 0, done.stderr
    return out


def test_readme_has_every_section(generated):
    readme = (generated / "README.md").read_text()
    for heading in (
        "## What ran",
        "## Warnings",
        "## How to read this report",
        "## The thesis' tables 1-4, for our run",
        "## The thesis' findings, checked",
        "## The thesis beside ours",
        "## What the stages change",
        "## Speedup and Karp-Flatt",
        "## The thesis' own metrics, recomputed",
        "## Figures",
        "## Runs without data",
    ):
        assert heading in readme
    for n in (1, 2, 3, 4):
        assert f"**Table {n} (" in readme


def test_table_4_mirrors_the_thesis_with_our_medians(generated):
    table4 = (generated / "tables/table4-optimized.md").read_text()
    assert "| scene | sequential | simd_tbb | simd_only | tbb_only | gpu |" in table4
    # Medians of the measured frames are the published times; warm-up frames (1.5x) excluded.
    assert "| random100 | 17553.0 | 2947.0 | 14102.0 | 4162.0 | 17.62 |" in table4
    assert "| default | 550.0 | 80.00 | 375.0 | 120.0 | 15.77 |" in table4
    assert "8 threads, 4 lanes NEON" in table4
    table2 = (generated / "tables/table2-original.md").read_text()
    assert "random20" not in table2  # rows only for scenes of our run


def test_metrics_reproduce_the_thesis_speedup_and_recomputed_karp_flatt(generated):
    metrics = (generated / "tables/metrics.md").read_text()
    row = next(line for line in metrics.splitlines() if line.startswith("| optimized | random100 | simd_tbb |"))
    cells = [c.strip() for c in row.strip("|").split("|")]
    assert cells[3] == names.BRUTE_FORCE  # the accel column
    assert cells[10].startswith("5.956") and cells[11] == "32" and cells[12] == "0.141"
    gpu = next(line for line in metrics.splitlines() if line.startswith("| original | random100 | gpu |"))
    assert "742.735" in gpu and "| 1024 |" in gpu and "Apple M1" in gpu


def test_stage_effects_show_what_each_step_buys(generated):
    effects = (generated / "tables/stage-effects.md").read_text()
    # thesis random100 simd_tbb: 23969 -> 7416 -> 2947 ms
    assert "| random100 | simd_tbb | 23969.0 | 7416.0 | 2947.0 | 3.23 (3.23) | 2.52 (2.52) |" in effects
    assert r"$\rightarrow$" in (generated / "tables/stage-effects.tex").read_text()


def test_thesis_karp_flatt_is_recomputed_and_said_so(generated):
    readme = (generated / "README.md").read_text()
    assert "Karp-Flatt values do not" in readme
    assert "original simd_tbb on random100: stated 0.68, recomputed 0.615 (p = 32)" in readme
    assert "optimized simd_tbb on random100: stated 0.206, recomputed 0.141 (p = 32)" in readme


def test_findings_of_the_thesis_own_times_are_the_thesis_figures(generated):
    """The fixture is the thesis' times: each claim's figure is the one its
    own table gives (findings.py), and half precision (no f16 run) is not measured."""
    found = pd.read_csv(generated / "data" / "thesis_findings.csv")
    measured = found[~found["claim"].isin(["8", "8b"])]
    assert all(math.isclose(m, t, rel_tol=1e-6) for m, t in zip(measured["measured"], measured["thesis"]))
    assert set(found.set_index("claim").loc[["8", "8b"], "verdict"]) == {"not measured"}
    assert (generated / "tables" / "thesis-findings.md").is_file()


def test_outlier_is_flagged_and_kept(generated):
    outliers = (generated / "data/outliers.csv").read_text().splitlines()
    assert len(outliers) == 2 and "random100-sequential-optimized-r1.csv,3," in outliers[1]
    summary = (generated / "tables/summary.md").read_text()
    row = next(line for line in summary.splitlines() if line.startswith("| optimized | random100 | sequential |"))
    cells = [c.strip() for c in row.strip("|").split("|")]
    assert cells[8] == "6" and cells[16] == "1"  # n = 6 measured frames, 1 outlier among them


def test_failed_run_is_listed(generated):
    assert (
        "random100-simd_tbb-custom r0 | failed | 1 | raytracer: fixture failure"
        in (generated / "README.md").read_text()
    )


def test_latex_and_figures_are_written(generated):
    tex = (generated / "tables/table4-optimized.tex").read_text()
    assert r"\begin{tabular}{lrrrrr}" in tex and r"simd\_tbb" in tex and r"\bottomrule" in tex
    for stem in ("render_ms", "frame_series", "distributions", "thesis_speedups"):
        assert (generated / f"plots/{stem}.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert b"<svg" in (generated / f"plots/{stem}.svg").read_bytes()[:400]
    assert not (generated / "plots/scaling.png").exists()  # one thread count per renderer
    assert not (generated / "plots/cost_vs_spheres.png").exists()  # two sphere counts (default, random100)
    assert "No cost-vs-spheres figure" in (generated / "README.md").read_text()
    assert not list(generated.rglob("*.tmp"))


def test_regeneration_is_identical_and_removes_stale_files(generated, tmp_path):
    inputs = report_writer.gather([FIXTURE])
    results = report_writer.compute(inputs)
    (tmp_path / "plots").mkdir()
    (tmp_path / "plots/old.png").write_bytes(b"stale")
    report_writer.write(inputs, results, tmp_path)
    assert not (tmp_path / "plots/old.png").exists()
    for rel in ("README.md", "tables/metrics.md", "tables/summary.tex", "data/summary.csv", "plots/render_ms.svg"):
        assert (tmp_path / rel).read_bytes() == (generated / rel).read_bytes(), rel


def test_thesis_tables_show_brute_force_only_and_every_accel_is_a_column():
    """The same runs again with another accel (3x faster): tables 1-4 keep
    their rows and gain a note; the configuration tables list both accels,
    each accel's speedup against the reference of the same accel."""
    inputs = report_writer.gather([FIXTURE])
    inputs.frames = inputs.frames[inputs.frames[names.STAGE] == "optimized"]  # table 4 only: half the time
    other = names.BVH
    faster = inputs.frames.assign(
        **{
            names.ACCEL: other,
            names.RENDER_MS: inputs.frames[names.RENDER_MS] / 3,
            names.RUN_ID: inputs.frames[names.RUN_ID] + "x",
        }
    )
    inputs_both = report_writer.ReportInputs(**{**vars(inputs), "frames": pd.concat([inputs.frames, faster])})
    alone, both = report_writer.compute(inputs), report_writer.compute(inputs_both)
    thesis_alone = [t for t in alone.tables if t.slug.startswith("table")]
    thesis_both = [t for t in both.tables if t.slug.startswith("table")]
    assert [t.rows for t in thesis_both] == [t.rows for t in thesis_alone]
    assert all(t.notes[:-1] == a.notes and other in t.notes[-1] for t, a in zip(thesis_both, thesis_alone))
    assert set(tables.headline_rows(both.summary[::-1])[names.ACCEL]) == {names.BRUTE_FORCE}  # whatever the order
    assert len(both.summary) == 2 * len(alone.summary)
    for t in both.tables:
        assert len(t.align) == len(t.headers) and all(len(row) == len(t.headers) for row in t.rows), t.slug
    met = both.metrics.set_index([names.SCENE, names.STAGE, names.RENDERER, names.ACCEL])["speedup"]
    for (scene, stage, renderer, _accel), s in met.items():
        assert s == pytest.approx(met[(scene, stage, renderer, names.BRUTE_FORCE)])
    summary = tables.to_markdown(tables.summary_table(both.summary))
    assert f"| optimized | random100 | simd_tbb | {other} |" in summary


def test_gpu_processor_override(tmp_path):
    inputs = report_writer.gather([FIXTURE], gpu_override=2048)
    met = report_writer.compute(inputs).metrics
    assert set(met[met["lanes"] == 0]["p"]) == {2048.0}


def test_report_cli_errors_name_the_file(tmp_path, repo_root):
    broken = tmp_path / "run"
    broken.mkdir()
    (broken / "x.csv").write_text("run_id,scene\n1,2\n")
    done = report_command(repo_root, broken, "-o", tmp_path / "out")
    assert done.returncode == 1
    assert f"report.py: {broken / 'x.csv'}: header does not match" in done.stderr
    assert not (tmp_path / "out").exists()


def test_markdown_escapes_pipes_and_latex_escapes_specials():
    t = tables.Table("t", "a_b", ["x|y"], [["50%"]], "l")
    assert "x\\|y" in tables.to_markdown(t)
    assert r"50\%" in tables.to_latex(t) and r"a\_b" in tables.to_latex(t)
