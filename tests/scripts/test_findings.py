"""The thesis' findings, checked (rtbench.findings): synthetic runs in which a
claim clearly holds, clearly does not, and straddles its line give the three
verdicts; a run without a configuration a claim needs gives `not measured`
naming it; the reason column names the optimisation and the cores where
they differ from the thesis'; and the section is in the report."""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest
from synthetic_runs import Environment, SyntheticConfig, agreement, write_run_dir

from rtbench import findings, names, report_writer

SCENE = "random100"
# The thesis' random100 times (docs/thesis.md "Published results"), in seconds
# rather than ms: a run with these ratios reproduces every claim.
THESIS_MS = {
    ("sequential", "original"): 38236,
    ("simd_tbb", "original"): 23969,
    ("simd_only", "original"): 116026,
    ("tbb_only", "original"): 8987,
    ("gpu", "original"): 51.48,
    ("sequential", "single-pass"): 17553,
    ("simd_tbb", "single-pass"): 7416,
    ("simd_only", "single-pass"): 36072,
    ("tbb_only", "single-pass"): 4162,
    ("gpu", "single-pass"): 17.62,
    ("sequential", "optimized"): 17553,
    ("simd_tbb", "optimized"): 2947,
    ("simd_only", "optimized"): 14102,
    ("tbb_only", "optimized"): 4162,
    ("gpu", "optimized"): 17.62,
}
# threads, lanes of each renderer as on the thesis' machine: 8 cores, 4 lanes.
SHAPE = {"sequential": (1, 1), "simd_tbb": (8, 4), "simd_only": (1, 4), "tbb_only": (8, 1), "gpu": (0, 0)}
# p of the GPU as the thesis took it (docs/thesis.md "Measurement").
GPU_P = 1024.0


def config(renderer: str, stage: str, precision: str = "") -> SyntheticConfig:
    threads, lanes = SHAPE[renderer]
    return SyntheticConfig(
        scene=SCENE, renderer=renderer, stage=stage, threads=threads, lanes=lanes, precision=precision
    )


def frames_around(ms: float, spread: float, n: int = 15) -> list[float]:
    """A warm-up frame, then n frames evenly within ms x (1 +- spread)."""
    return [ms * 3, *(ms * (1 + spread * k) for k in np.linspace(-1, 1, n))]


def checked(tmp_path, times=None, spread=0.01, spreads=None, env=None, leave_out=(), counters=None, **more):
    """The findings table of a synthetic run with `times` (ms by (renderer,
    stage), or (renderer, stage, precision); default the thesis'), each
    configuration's frames within +-spread (`spreads` per configuration),
    less the configurations in `leave_out`, `counters` and `more`
    (agreements, unavailable) as write_run_dir takes them; by claim."""
    times = dict(THESIS_MS if times is None else times)
    spreads = spreads or {}
    runs = {
        config(*key): [frames_around(ms / 1000, spreads.get(key, spread))]
        for key, ms in times.items()
        if key not in leave_out and key[0] not in leave_out and key[1] not in leave_out
    }
    run = write_run_dir(tmp_path / "run", runs, env=env, counters=counters, **more)
    results = report_writer.compute(report_writer.gather([run], gpu_override=GPU_P))
    return {r["claim"]: r for r in results.findings.to_dict("records")}


def test_verdict_of_a_ci_against_a_region():
    assert findings.verdict(1.2, 1.4, 1.0, 2.0) == findings.REPRODUCED
    assert findings.verdict(2.1, 2.5, 1.0, 2.0) == findings.NOT_REPRODUCED
    assert findings.verdict(0.5, 0.9, 1.0, math.inf) == findings.NOT_REPRODUCED
    assert findings.verdict(1.8, 2.2, 1.0, 2.0) == findings.INCONCLUSIVE
    assert findings.verdict(math.nan, math.nan, 1.0, 2.0) == findings.NOT_MEASURED


def test_optimisation_from_flags_or_build_type():
    assert findings.optimisation("-O3 -DNDEBUG", "Release") == "-O3"
    assert findings.optimisation("-O0 -g", "PaperO0") == "-O0"
    assert findings.optimisation("", "PaperO0") == "-O0"
    assert findings.optimisation("", "Release") == "-O3"


def test_every_claim_has_a_region_and_the_f16_row_names_its_fields():
    for claim in findings.CLAIMS:
        assert claim.low < claim.high, claim.key
        assert claim.refs, claim.key
    keys = [c.key for c in findings.CLAIMS]
    assert len(set(keys)) == len(keys)


def test_the_thesis_own_times_reproduce_every_claim(tmp_path):
    rows = checked(tmp_path)
    measured = {k: r for k, r in rows.items() if k not in ("8", "8b")}
    assert {k: r["verdict"] for k, r in measured.items()} == {k: findings.REPRODUCED for k in measured}
    # The figure is the thesis' own (its times, its p) and the CI holds it.
    for key, r in measured.items():
        assert r["measured"] == pytest.approx(r["thesis"], rel=1e-6), key
        assert r["ci_low"] <= r["measured"] <= r["ci_high"], key
    assert rows["1"]["measured"] == pytest.approx(38236 / 23969)
    assert rows["2"]["measured"] == pytest.approx(38236 / 8987 / 8)
    # Claim 7: e from the run's own p (8 threads x 4 lanes; the GPU's --gpu-p).
    s = 17553 / 2947
    assert rows["7a"]["measured"] == pytest.approx((1 / s - 1 / 32) / (1 - 1 / 32))
    assert rows["7a"]["thesis_stated"] == pytest.approx(0.206)
    # Reproduced: no reason given.
    assert all(r["reason"] == "" for r in measured.values())


def test_half_precision_without_f16_runs_is_not_measured_and_says_how_to_run_it(tmp_path):
    rows = checked(tmp_path)
    for key, renderer in (("8", "simd_only"), ("8b", "gpu")):
        assert rows[key]["verdict"] == findings.NOT_MEASURED, key
        assert f"no f16 run of {SCENE}/{renderer}/original" in rows[key]["reason"], key
        assert "precisions" in rows[key]["reason"], key
    assert rows["8"]["thesis_stated"] == 2.0
    assert "not a thesis claim" in rows["8b"]["text"]


# An f16 image the render model's rule fails, and one it passes (docs/render-model.md section 8).
RUINED = agreement(0.62, 21.5, 140)
FINE = agreement(0.9991, 48.0, 6)
IDENTICAL = agreement(1.0, None, 0)


def f16_run(tmp_path, renderer, speedup, image, f32_image=IDENTICAL, spread=0.01):
    """The thesis' run plus `renderer` at original in f16, `speedup` times
    faster than its f32 time, each with the agreement object given (None:
    no --agreement)."""
    times = {**THESIS_MS, (renderer, "original", "f16"): THESIS_MS[(renderer, "original")] / speedup}
    agreed = {config(renderer, "original"): f32_image, config(renderer, "original", "f16"): image}
    return checked(tmp_path, times, spread=spread, agreements={k: v for k, v in agreed.items() if v})


@pytest.mark.parametrize(
    "speedup, image, expected",
    [
        (2.0, RUINED, findings.REPRODUCED),
        (2.0, FINE, findings.NOT_REPRODUCED),  # twice as fast, but the image is fine
        (1.0, RUINED, findings.NOT_REPRODUCED),  # ruined, but no faster
        (5.0, RUINED, findings.NOT_REPRODUCED),  # far more than about 2x
        (2.0, None, findings.NOT_MEASURED),  # no --agreement: the image part is unknown
    ],
)
def test_half_precision_needs_about_twice_the_speed_and_a_ruined_image(tmp_path, speedup, image, expected):
    row = f16_run(tmp_path, "simd_only", speedup, image)["8"]
    assert row["verdict"] == expected
    assert row["measured"] == pytest.approx(speedup, rel=1e-6)
    assert row["ci_low"] <= row["measured"] <= row["ci_high"]
    assert "f32: simd_only" in row["configurations"] and "f16: simd_only" in row["configurations"]
    if image is RUINED:
        assert "62.0%, 21.5 dB, max 140: fails" in row["reason"]
    if image is None:
        assert "no --agreement" in row["reason"]


def test_half_precision_straddling_about_2x_is_inconclusive(tmp_path):
    # 3x is the upper line of "about 2x"; frames spread +-30 % put the CI across it.
    row = f16_run(tmp_path, "simd_only", 2.0 * findings.ABOUT, RUINED, spread=0.3)["8"]
    assert row["ci_low"] < 2.0 * findings.ABOUT < row["ci_high"]
    assert row["verdict"] == findings.INCONCLUSIVE


def test_a_refused_simd_f16_is_not_measured_with_the_probe_line_and_the_gpu_row_shows(tmp_path):
    refusal = "exit 2: --precision f16: the CPU's Highway target (AVX3) has no native f16 arithmetic"
    times = {**THESIS_MS, ("gpu", "original", "f16"): THESIS_MS[("gpu", "original")] / 2}
    rows = checked(
        tmp_path,
        times,
        agreements={config("gpu", "original", "f16"): RUINED},
        unavailable={config("simd_only", "original", "f16"): refusal},
    )
    assert rows["8"]["verdict"] == findings.NOT_MEASURED
    assert f"f16 refused: {refusal}" in rows["8"]["reason"]
    assert rows["8b"]["verdict"] == findings.REPRODUCED
    assert rows["8b"]["measured"] == pytest.approx(2.0, rel=1e-6)
    # The f16 run stays out of every other claim: claim 6a still sees the f32 gpu.
    assert rows["6a"]["measured"] == pytest.approx(38236 / 51.48, rel=1e-6)


def test_clearly_not_reproduced(tmp_path):
    times = dict(THESIS_MS)
    times[("simd_tbb", "original")] = 38236 / 20  # 20x, not "only about 1.6x"
    times[("simd_only", "original")] = 38236 / 3  # faster than sequential
    times[("gpu", "optimized")] = 17553 / 20  # 20x: not three orders of magnitude
    rows = checked(tmp_path, times)
    assert rows["1"]["verdict"] == findings.NOT_REPRODUCED
    assert rows["3"]["verdict"] == findings.NOT_REPRODUCED
    assert rows["6b"]["verdict"] == findings.NOT_REPRODUCED
    # ... and a large e for the GPU: not in the thesis' near-zero regime.
    assert rows["7b"]["verdict"] == findings.NOT_REPRODUCED
    assert rows["1"]["measured"] == pytest.approx(20, rel=1e-6)
    assert rows["5b"]["verdict"] == findings.REPRODUCED


def test_a_ci_straddling_the_line_is_inconclusive(tmp_path):
    times = dict(THESIS_MS)
    # S = 2.4 exactly, the upper line of "about 1.6x", with frames spread +-30 %.
    times[("simd_tbb", "original")] = 38236 / 2.4
    rows = checked(tmp_path, times, spreads={("simd_tbb", "original"): 0.3})
    row = rows["1"]
    assert row["verdict"] == findings.INCONCLUSIVE
    assert row["ci_low"] < 1.6 * findings.ABOUT < row["ci_high"]
    # The same figure with tight frames lies on one side or the other, not across.
    tight = checked(tmp_path / "tight", {**times, ("simd_tbb", "original"): 38236 / 2.0})
    assert tight["1"]["verdict"] == findings.REPRODUCED


def test_missing_configurations_are_not_measured_and_named(tmp_path):
    rows = checked(tmp_path, leave_out=("original", "gpu"))
    for key in ("1", "2", "3", "4a", "4b", "6a"):
        assert rows[key]["verdict"] == findings.NOT_MEASURED, key
        assert f"{SCENE}/sequential/original" in rows[key]["reason"], key
    assert f"{SCENE}/gpu/optimized" in rows["6b"]["reason"]
    assert rows["7b"]["verdict"] == findings.NOT_MEASURED
    # The claims that need neither still get a verdict.
    assert rows["5a"]["verdict"] == findings.REPRODUCED
    assert rows["7a"]["verdict"] == findings.REPRODUCED


def test_the_reason_names_optimisation_and_cores(tmp_path):
    times = dict(THESIS_MS)
    times[("simd_tbb", "original")] = 38236 / 20
    o3 = checked(tmp_path / "o3", times, env=Environment(logical_cores=2, cpu_model="Test CPU"))
    reason = o3["1"]["reason"]
    assert "built -O3 (thesis -O0)" in reason
    assert "2 logical cores (Test CPU), 8 threads" in reason
    o0 = checked(
        tmp_path / "o0",
        times,
        env=Environment(logical_cores=16, build_type="PaperO0", compiler_flags="-O0 -g"),
    )
    assert "built" not in o0["1"]["reason"]
    assert "16 logical cores" in o0["1"]["reason"]


def lane_counters(frames: int, slots: int, active: int) -> dict[str, list]:
    """Counter columns of `frames` frames in which every kind of lane work
    had `slots` lane slots, `active` of them active."""
    per_frame = {"rays": 100, "rays_per_depth": "60/40", "node_visits": 0, "sphere_tests": 50}
    for kind_slots, kind_active in names.LANE_WORK.values():
        per_frame[kind_slots], per_frame[kind_active] = slots, active
    return {column: [value] * frames for column, value in per_frame.items()}


def test_the_reason_names_the_masked_lane_work_where_the_run_has_counters(tmp_path):
    times = dict(THESIS_MS)
    times[("simd_tbb", "original")] = 38236 / 20
    frames = len(frames_around(1.0, 0.01))
    rows = checked(tmp_path, times, counters={config("simd_tbb", "original"): lane_counters(frames, 400, 100)})
    assert "simd_tbb original masks off 75.0% of its lane work" in rows["1"]["reason"]
    # Without counters the reason says nothing of lanes masked off.
    assert "masks off" not in checked(tmp_path / "plain", times)["1"]["reason"]


def test_the_report_has_the_section_and_its_csv(tmp_path):
    run = write_run_dir(tmp_path / "run", {config(*k): [frames_around(ms / 1000, 0.01)] for k, ms in THESIS_MS.items()})
    assert report_writer.main([str(run), "-o", str(tmp_path / "report"), "-q", "--gpu-p", str(GPU_P)]) == 0
    readme = (tmp_path / "report" / "README.md").read_text()
    assert f"## {findings.TITLE}" in readme
    assert (tmp_path / "report" / "tables" / "thesis-findings.tex").is_file()
    with (tmp_path / "report" / "data" / "thesis_findings.csv").open() as f:
        rows = list(csv.DictReader(f))
    assert [r["claim"] for r in rows] == [*(c.key for c in findings.CLAIMS), "8", "8b"]
    assert {r["verdict"] for r in rows} == {findings.REPRODUCED, findings.NOT_MEASURED}
