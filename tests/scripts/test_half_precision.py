"""The precision axis (schema: precisions, the CSV's precision column, the
metadata's agreement object): a CSV without the column loads as f32;
profiles run a renderer per precision with --precision and --agreement,
and refuse precisions where the raytracer would; the bench probes f16 once
per renderer; the report keeps f16 out of its comparisons and sets it beside
f32 in its half-precision section; and report.py --findings sets the
verdicts of several runs side by side."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import pytest
from synthetic_runs import Environment, SyntheticConfig, agreement, table_rows, write_run_dir

from rtbench import configurations, load, names, precision, profiles, report_writer

# The thesis' scene and stage of claim 8 (findings.F16_CLAIMS).
AT = {"scene": "random100", "stage": "original"}
F32_RUN = SyntheticConfig(renderer="simd_only", threads=1, lanes=16, precision="f32", **AT)
F16_RUN = SyntheticConfig(renderer="simd_only", threads=1, lanes=16, precision="f16", **AT)
SEQUENTIAL = SyntheticConfig(renderer="sequential", threads=1, lanes=1, **AT)
REFUSAL = "exit 2: --precision f16: the Highway target AVX3 has no native f16 arithmetic"


def test_a_csv_without_the_precision_column_loads_as_f32(tmp_path):
    run = write_run_dir(tmp_path / "run", {SEQUENTIAL: [[5.0, 4.0, 4.1]]})
    path = next((run / load.FRAMES_DIR).glob("*.csv"))
    rows = list(csv.reader(path.open()))
    drop = rows[0].index(names.PRECISION)
    with path.open("w", newline="") as f:
        csv.writer(f, lineterminator="\n").writerows(r[:drop] + r[drop + 1 :] for r in rows)
    frames = load.load_runs([run])
    assert set(frames[names.PRECISION]) == {names.F32}
    assert frames[names.WITHIN_TOLERANCE].isna().all()


def test_the_agreement_object_loads_and_a_null_psnr_means_identical(tmp_path):
    agreed = {F32_RUN: agreement(1.0, None, 0), F16_RUN: agreement(0.5, 20.0, 90)}
    run = write_run_dir(tmp_path / "run", {F32_RUN: [[3, 2, 2]], F16_RUN: [[2, 1, 1]]}, agreements=agreed)
    frames = load.load_runs([run])
    half = frames[frames[names.PRECISION] == names.F16]
    assert set(half[names.WITHIN_TOLERANCE]) == {0.5} and set(half[names.MAX_CHANNEL_DIFFERENCE]) == {90}
    assert set(frames.loc[frames[names.PRECISION] == names.F32, names.PSNR_DB]) == {math.inf}


def test_section_8s_rule_decides_whether_an_image_agrees():
    assert precision.agrees(0.995, 40.0) == 1.0
    assert precision.agrees(0.994, 60.0) == 0.0
    assert precision.agrees(1.0, 39.9) == 0.0
    assert precision.agrees(1.0, math.inf) == 1.0
    assert math.isnan(precision.agrees(math.nan, math.nan))


def profile(renderers: dict) -> profiles.Profile:
    raw = {"description": "t", "scenes": ["default"], "stages": ["original"], "renderers": renderers}
    return profiles.parse_profile(raw, Path("t.toml"))


def test_precisions_expand_into_runs_with_the_flag_and_agreement_adds_its_own():
    spec = {"simd_only": {"precisions": ["f32", "f16"], "agreement": True}, "sequential": {}}
    configs = configurations.expand(profile(spec), [Path("scenes/default.json")], 2)
    argvs = {c.id: c.argv(Path("rt"), Path("a.csv"), Path("a.json")) for c in configs}
    ids = ["default-sequential-original", "default-simd_only-original", "default-simd_only-original-f16"]
    assert sorted(argvs) == ids
    f16 = argvs["default-simd_only-original-f16"]
    assert f16[f16.index("--precision") + 1] == "f16"
    for config_id in ("default-simd_only-original", "default-simd_only-original-f16"):
        assert "--agreement" in argvs[config_id] and "--precision" in argvs[config_id]
    assert "--precision" not in argvs["default-sequential-original"]
    assert "--agreement" not in argvs["default-sequential-original"]
    # The bench probes the f16 runs once more, with the flag; the f32 runs with the renderer's own probe.
    probes = {c.id: configurations.probe_args(c.describe()) for c in configs}
    assert probes == {
        "default-sequential-original": (),
        "default-simd_only-original": (),
        "default-simd_only-original-f16": ("--precision", "f16"),
    }


@pytest.mark.parametrize("renderer", ["sequential", "tbb_only", "gpu_rt", "embree"])
def test_precisions_of_a_renderer_without_f16_is_a_profile_error_naming_file_and_key(renderer):
    with pytest.raises(profiles.ProfileError, match=rf"t\.toml: renderers\.{renderer}\.precisions: .*simd_tbb"):
        profile({renderer: {"precisions": ["f32", "f16"]}})


def test_an_unknown_or_repeated_precision_is_a_profile_error():
    with pytest.raises(profiles.ProfileError, match="precisions"):
        profile({"gpu": {"precisions": ["f64"]}})
    with pytest.raises(profiles.ProfileError, match="once"):
        profile({"gpu": {"precisions": ["f16", "f16"]}})


@pytest.mark.parametrize("name", ["paper", "paper-o0"])
def test_the_paper_profiles_run_the_ablation_for_simd_only_and_gpu_with_agreement(name):
    configs = configurations.expand(profiles.load_profile(name), [Path("scenes/random100.json")], 2)
    halves = {c.renderer for c in configs if c.precision == names.F16}
    assert halves == {"simd_only", "gpu"}
    assert all(c.agreement for c in configs if c.renderer in halves)


def half_precision_run(tmp_path: Path) -> Path:
    """simd_only at f32 and f16 (twice as fast, a ruined image), sequential,
    and a gpu f16 the probe refused."""
    times = {SEQUENTIAL: [[9, 8, 8.1, 7.9]], F32_RUN: [[5, 4, 4.1, 3.9]], F16_RUN: [[3, 2, 2.05, 1.95]]}
    agreed = {F32_RUN: agreement(0.999, 55.0, 4), F16_RUN: agreement(0.71, 24.0, 120)}
    refused = {SyntheticConfig(renderer="gpu", threads=0, lanes=0, precision="f16", **AT): REFUSAL}
    return write_run_dir(tmp_path / "run", times, agreements=agreed, unavailable=refused)


def test_the_report_keeps_f16_out_of_its_comparisons_and_shows_it_in_its_own_section(tmp_path):
    out = tmp_path / "report"
    assert report_writer.main([str(half_precision_run(tmp_path)), "-o", str(out), "-q"]) == 0
    readme = (out / "README.md").read_text()
    assert f"## {precision.TITLE}" in readme
    rows = table_rows((out / "tables" / f"{precision.SLUG}.md").read_text())
    simd = next(r for r in rows if r[2] == "simd_only")
    assert simd[4:7] == ["4.000", "2.000", simd[6]] and simd[6].startswith("2.00 [")
    assert simd[7].endswith(": agrees") and simd[8] == "71.0%, 24.0 dB, max 120: fails"
    assert ["–", "–", "gpu", "f16 refused", "–", "–", "–", "", REFUSAL] in rows
    with (out / "data" / "half_precision.csv").open() as f:
        (data,) = list(csv.DictReader(f))
    assert float(data[precision.SPEEDUP]) == pytest.approx(2.0)
    # The metrics (speedup over sequential) see the f32 simd_only only.
    with (out / "data" / "metrics.csv").open() as f:
        metrics = list(csv.DictReader(f))
    assert [(m[names.RENDERER], m[names.PRECISION]) for m in metrics] == [("simd_only", "f32")]
    # The summary lists every configuration, the f16 one labelled.
    assert "none f16" in (out / "tables" / "summary.md").read_text()
    assert f"| every gpu run (1) | skipped: its probe failed | | {REFUSAL} |" in readme


def test_findings_side_by_side_one_column_per_run(tmp_path):
    first = half_precision_run(tmp_path / "a")
    second = write_run_dir(
        tmp_path / "b" / "run-o0",
        {SEQUENTIAL: [[9, 8, 8.1, 7.9]], F32_RUN: [[5, 4, 4.1, 3.9]]},
        env=Environment(logical_cores=16, cpu_model="Other CPU", build_type="PaperO0", compiler_flags="-O0"),
    )
    out = tmp_path / "verdicts.md"
    assert report_writer.main(["--findings", str(first), str(second), "-o", str(out), "-q"]) == 0
    text = out.read_text()
    header = next(line for line in text.splitlines() if line.startswith("| #"))
    assert "2 cores, -O3 (Synthetic CPU; run)" in header and "16 cores, -O0 (Other CPU; run-o0)" in header
    rows = {r[0]: r for r in table_rows(text)}
    assert rows["3"][3].startswith("**not reproduced** 2 [") and rows["3"][4].startswith("**not reproduced** 2 [")
    assert rows["8"][3].startswith("**reproduced** 2 [")
    assert rows["8"][4] == "**not measured**"
    assert rows["8b"][3] == "**not measured**"
    assert list(rows) == ["1", "2", "3", "4a", "4b", "5a", "5b", "6a", "6b", "7a", "7b", "8", "8b"]
