"""compare (rtbench.compare): synthetic runs with a known shift, the same data
twice, configurations on one side only, environment differences, bad input,
and the statistics it rests on."""

import json
import math
import tarfile

import numpy as np
import pytest
from synthetic_runs import Environment, SyntheticConfig, write_run_dir

from rtbench import compare, compare_cli, compare_input, compare_output

FAST = SyntheticConfig(renderer="simd_tbb", threads=2, lanes=16)
SLOW = SyntheticConfig(renderer="sequential", threads=1, lanes=1)
EXTRA = SyntheticConfig(scene="default")


def frame_times(ms: float, seed: int, repetitions: int = 3, frames: int = 10, noise: float = 0.01) -> list[list[float]]:
    """Warm-up frame (2x) + measured frames with 1 % Gaussian noise, per repetition."""
    rng = np.random.default_rng(seed)
    return [[2 * ms, *(ms * (1 + noise * rng.standard_normal(frames)))] for _ in range(repetitions)]


def scaled(runs: dict, factor: float) -> dict:
    return {c: [[t * factor for t in rep] for rep in reps] for c, reps in runs.items()}


@pytest.fixture
def base_runs():
    return {FAST: frame_times(10.0, 1), SLOW: frame_times(40.0, 2)}


def run_compare(capsys, *argv):
    code = compare_cli.main([str(a) for a in argv], prog="compare.py")
    out, err = capsys.readouterr()
    return code, out, err


def test_a_ten_percent_slowdown_is_slower(tmp_path, base_runs, capsys):
    base = write_run_dir(tmp_path / "base", base_runs)
    new = write_run_dir(tmp_path / "new", {FAST: scaled({FAST: base_runs[FAST]}, 1.10)[FAST], SLOW: base_runs[SLOW]})
    code, out, _ = run_compare(capsys, base, new, "-o", tmp_path / "out")
    assert code == 0  # no --fail-above: a report, not a gate
    result = json.loads((tmp_path / "out" / "compare.json").read_text())
    by_label = {c["label"]: c for c in result["configurations"]}
    slowed = by_label["random20/simd_tbb/optimized/t2/l16"]
    assert slowed["verdict"] == "slower" and slowed["ratio"] == pytest.approx(1.10)
    assert slowed["ci_low"] > 1.0 and slowed["p_value"] < 0.05
    assert by_label["random20/sequential/optimized"]["verdict"] == "~"
    assert result["verdicts"] == {"faster": 0, "slower": 1, "~": 1}
    assert result["geomean_ratio"] == pytest.approx(math.sqrt(1.10))
    assert (
        "slower" in out
        and (tmp_path / "out" / "compare.png").is_file()
        and (tmp_path / "out" / "compare.svg").is_file()
    )
    assert "| random20/simd_tbb/optimized/t2/l16 | 10.0" in (tmp_path / "out" / "compare.md").read_text()


def test_a_speedup_is_faster(tmp_path, base_runs):
    base = write_run_dir(tmp_path / "base", base_runs)
    new = write_run_dir(tmp_path / "new", scaled(base_runs, 0.8))
    cmp = compare_input.compare_paths([base], [new], compare.Options())
    assert list(cmp.rows["verdict"]) == ["faster", "faster"]
    assert cmp.geomean == pytest.approx(0.8)


def test_fail_above_gates_on_significant_slowdowns_only(tmp_path, base_runs, capsys):
    base = write_run_dir(tmp_path / "base", base_runs)
    new = write_run_dir(tmp_path / "new", scaled(base_runs, 1.10))
    code, _, err = run_compare(capsys, base, new, "--fail-above", "5%", "-q")
    assert code == 1 and "random20/simd_tbb/optimized/t2/l16 is slower by more than 5%" in err
    assert run_compare(capsys, base, new, "--fail-above", "0.2", "-q")[0] == 0
    # Slower by 10 %, but called ~ under a 15 % noise threshold: nothing to fail.
    assert run_compare(capsys, base, new, "--fail-above", "5%", "--noise", "15%", "-q")[0] == 0


def test_the_same_data_twice_is_all_unchanged(tmp_path, base_runs, capsys):
    base = write_run_dir(tmp_path / "base", base_runs)
    code, out, _ = run_compare(capsys, base, base, "--fail-above", "0", "-o", tmp_path / "out")
    result = json.loads((tmp_path / "out" / "compare.json").read_text())
    assert code == 0 and result["verdicts"] == {"faster": 0, "slower": 0, "~": 2}
    assert all(c["ratio"] == 1.0 and c["p_value"] == pytest.approx(1.0) for c in result["configurations"])
    assert result["geomean_ratio"] == 1.0 and result["environment_differences"] == []
    assert "agree in every fact" in out


def test_configurations_on_one_side_only_are_listed(tmp_path, base_runs):
    base = write_run_dir(tmp_path / "base", {**base_runs, EXTRA: frame_times(5.0, 3)})
    only_new = SyntheticConfig(renderer="simd_tbb", threads=1, lanes=16)
    new = write_run_dir(tmp_path / "new", {FAST: base_runs[FAST], only_new: frame_times(20.0, 4)})
    cmp = compare_input.compare_paths([base], [new], compare.Options())
    assert list(cmp.rows["label"]) == ["random20/simd_tbb/optimized/t2/l16"]
    assert cmp.only_base == ["default/simd_tbb/optimized/t2/l16", "random20/sequential/optimized"]
    assert cmp.only_new == ["random20/simd_tbb/optimized/t1/l16"]
    text = compare_output.markdown(cmp)
    assert "**Configurations only in base (2)**" in text and "- random20/simd_tbb/optimized/t1/l16" in text


def test_environment_differences_come_from_the_metadata(tmp_path, base_runs):
    base = write_run_dir(tmp_path / "base", base_runs)
    other = Environment(
        cpu_model="Intel Xeon",
        logical_cores=16,
        compiler="GNU 14.3.0",
        git_commit="b" * 40,
        device="NVIDIA H200",
        libraries={"onetbb": "2022.0.0"},
    )
    new = write_run_dir(tmp_path / "new", base_runs, env=other)
    cmp = compare_input.compare_paths([base], [new], compare.Options())
    differences = {fact: (b, n) for fact, b, n in cmp.differences}
    assert differences["CPU"] == (["Synthetic CPU"], ["Intel Xeon"])
    assert differences["logical cores"] == (["2"], ["16"])
    assert differences["compiler"] == (["GNU 12.2.0"], ["GNU 14.3.0"])
    assert differences["git commit"] == (["a" * 12], ["b" * 12])
    assert differences["Vulkan device"] == (["llvmpipe (LLVM 15.0.6, 256 bits)"], ["NVIDIA H200"])
    assert differences["library onetbb"] == (["2021.8.0"], ["2022.0.0"])
    assert "OS" not in differences and "Nix" not in differences  # the same on both sides
    # The device is the machine's: the configurations still match across it.
    assert len(cmp.rows) == 2


def test_all_cores_matches_each_machines_whole_cpu(tmp_path, base_runs):
    base = write_run_dir(tmp_path / "base", base_runs, env=Environment(logical_cores=2))
    whole = SyntheticConfig(renderer="simd_tbb", threads=16, lanes=16)
    new = write_run_dir(
        tmp_path / "new", {whole: frame_times(2.0, 5), SLOW: base_runs[SLOW]}, env=Environment(logical_cores=16)
    )
    exact = compare_input.compare_paths([base], [new], compare.Options())
    assert exact.only_base == ["random20/simd_tbb/optimized/t2/l16"]
    matched = compare_input.compare_paths([base], [new], compare.Options(all_cores=True))
    assert "random20/simd_tbb/optimized/t2→16/l16" in list(matched.rows["label"]) and not matched.only_base


def test_a_key_that_pools_different_configurations_is_bad_input(tmp_path, base_runs, capsys):
    first = write_run_dir(tmp_path / "a", base_runs)
    second = write_run_dir(tmp_path / "b", base_runs, env=Environment(device="NVIDIA H200"))
    code, _, err = run_compare(capsys, "--base", first, second, "--new", first)
    assert code == 2 and "more than one device" in err and "--key-with device" in err
    assert run_compare(capsys, "--base", first, second, "--new", first, "--key-with", "device", "-q")[0] == 0


def test_a_corrupted_csv_is_exit_2_naming_the_file(tmp_path, base_runs, capsys):
    base = write_run_dir(tmp_path / "base", base_runs)
    new = write_run_dir(tmp_path / "new", base_runs)
    broken = next((new / "frames").glob("*.csv"))
    lines = broken.read_text().splitlines()
    broken.write_text("\n".join([*lines[:3], lines[3].replace(",", ";"), *lines[4:]]) + "\n")
    code, _out, err = run_compare(capsys, base, new, "-o", tmp_path / "out")
    assert code == 2 and str(broken) in err and "line 4" in err
    assert not (tmp_path / "out").exists()  # nothing half-written
    code, _, err = run_compare(capsys, base, tmp_path / "absent")
    assert code == 2 and str(tmp_path / "absent") in err


def test_bad_arguments_are_exit_2(tmp_path, capsys):
    for argv in ([tmp_path], [tmp_path, tmp_path, tmp_path], [tmp_path, tmp_path, "--alpha", "2"]):
        with pytest.raises(SystemExit) as stop:
            compare_cli.main([str(a) for a in argv], prog="compare.py")
        assert stop.value.code == 2


def test_a_run_archive_compares_as_its_directory(tmp_path, base_runs):
    base = write_run_dir(tmp_path / "20260101T000000Z-synthetic", base_runs)
    packed = tmp_path / "packed.tar.xz"
    with tarfile.open(packed, "w:xz") as tar:
        tar.add(base, arcname=base.name)
    cmp = compare_input.compare_paths([packed], [base], compare.Options())
    assert set(cmp.rows["verdict"]) == {"~"} and cmp.base.run_names == [base.name]


def test_an_archive_reaching_outside_its_directory_is_refused(tmp_path, base_runs, capsys):
    base = write_run_dir(tmp_path / "run", base_runs)
    evil = tmp_path / "evil.tar.xz"
    with tarfile.open(evil, "w:xz") as tar:
        tar.add(base, arcname="run")
        tar.add(base / "manifest.json", arcname="run/../escaped.json")
    code, _, err = run_compare(capsys, evil, base)
    assert code == 2 and str(evil) in err and "outside" in err
    assert not (tmp_path.parent / "escaped.json").exists()


# --- the statistics ----------------------------------------------------------------


def test_verdict_needs_every_test():
    assert compare.verdict(1.2, (1.1, 1.3), 0.001, 0.05, 0.05) == "slower"
    assert compare.verdict(0.8, (0.7, 0.9), 0.001, 0.05, 0.05) == "faster"
    assert compare.verdict(1.2, (1.1, 1.3), 0.05, 0.05, 0.05) == "~"  # p not below alpha
    assert compare.verdict(1.2, (0.99, 1.3), 0.001, 0.05, 0.05) == "~"  # the CI spans 1
    assert compare.verdict(1.03, (1.02, 1.04), 0.001, 0.05, 0.05) == "~"  # under the noise threshold
    assert compare.verdict(math.nan, (math.nan, math.nan), math.nan, 0.05, 0.05) == "~"


def test_mann_whitney_is_scipys_two_sided_test():
    # Exact two-sided p of two fully separated samples of 3: 2 / C(6, 3) = 0.1.
    assert compare.mann_whitney_p([1, 2, 3], [4, 5, 6]) == pytest.approx(0.1)
    assert compare.mann_whitney_p([5, 5, 5], [5, 5]) == 1.0
    assert math.isnan(compare.mann_whitney_p([], [1.0]))


def test_ratio_ci_is_seeded_and_covers_the_true_ratio():
    rng = np.random.default_rng(7)
    base, new = 10 + rng.standard_normal(40) * 0.1, 12 + rng.standard_normal(40) * 0.1
    ci = compare.ratio_ci(base, new)
    assert ci == compare.ratio_ci(base, new)
    assert ci[0] < 1.2 < ci[1] and ci[1] - ci[0] < 0.05
    assert all(math.isnan(v) for v in compare.ratio_ci([], [1.0]))  # no data, no interval
    assert compare.geometric_mean([0.5, 2.0]) == pytest.approx(1.0)
